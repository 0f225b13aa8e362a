# Runs speed_table on one mesh (MESH) once and checks that the table has every system's rows,
# with numbers, and the targets and machine lines below it.
execute_process(COMMAND ${EXE} ${MESH} --repeats 1 OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "speed_table exited with ${rc}:\n${out}")
endif()
set(num "[0-9]+\\.[0-9]+")
foreach(row
    "femsimp defaults \\(fe\\) \\| 1 \\| [0-9]+ \\| ${num} \\| ${num} \\| – \\| ${num} \\| ${num} \\| target [0-9]+ V (not )?reached"
    "femsimp defaults \\(fe\\) \\| 2 \\| [0-9]+ \\| ${num} \\| ${num} \\| ${num}× \\|"
    "femsimp --preset paper --min-angle 0 \\| 1 \\| [0-9]+ \\| ${num} \\|"
    "femsimp --preset paper --min-angle 0 \\| 2 \\| [0-9]+ \\| ${num} \\| ${num} \\| ${num}× \\|"
    "meshoptimizer meshopt_simplify \\| 1 \\| [0-9]+ \\| ${num} \\| 1\\.00 \\|"
    "OpenMesh Decimater \\| 1 \\| [0-9]+ \\| ${num} \\|"
    "Machine: [0-9]+ cores"
    "not in this run: the blade targets are not measured")
  if(NOT out MATCHES "${row}")
    message(FATAL_ERROR "speed_table's output lacks a line matching '${row}':\n${out}")
  endif()
endforeach()
