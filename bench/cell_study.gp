# Speedup plot of bench/cell_study.sh. Variables (gnuplot -e): datadir, outfile, kind
# ("modeled": cellsim cycle model; "measured": host wall clock on the study machine's cores).
if (!exists("kind")) kind = "modeled"
set terminal svg size 720,480 dynamic font "sans,12"
set output outfile
set datafile missing "NaN"
set key top left Left reverse opaque box font ",10"
set grid
set logscale x 2
set xrange [1:32]
set xtics (1, 2, 4, 8, 16, 32)
set xlabel "SPEs (cell back end)"
if (kind eq "modeled") {
  set title "Cell back end speedup, modeled (cellsim cycle model)"
  set ylabel "modeled speedup = cycles(1 SPE) / cycles(N)"
  set yrange [0:33]
} else {
  set title "Cell back end speedup, measured (2 host cores) -- host wall clock"
  set ylabel "measured wall-clock speedup (2 host cores)"
  set yrange [0:*]
}
f = datadir."/".kind.".dat"
if (kind eq "modeled") {
  plot f using 1:2 with lines dashtype 2 lc rgb "gray40" title "ideal", \
       f using 1:3 with linespoints pt 7 title "fandisk geometric (modeled)", \
       f using 1:4 with linespoints pt 5 title "fandisk topology only (modeled)", \
       f using 1:5 with linespoints pt 9 title "blade3 geometric (modeled)", \
       f using 1:6 with linespoints pt 11 title "blade3 topology only (modeled)", \
       f using 1:7 with linespoints pt 13 dashtype 3 title "blade3 geometric, --min-angle 1 (modeled)", \
       f using 1:8 with linespoints pt 6 lc rgb "dark-red" dashtype 4 title "blade3 geometric, pass 1 only (modeled)", \
       f using 1:9 with linespoints pt 4 lc rgb "dark-blue" dashtype 4 title "blade3 geometric --min-angle 1, pass 1 only (modeled)"
} else {
  set yrange [0:2.5]
  plot f using 1:($1 < 2 ? $1 : 2) with lines dashtype 2 lc rgb "gray40" title "ideal on 2 host cores", \
       f using 1:3 with linespoints pt 7 title "fandisk geometric (measured, 2 host cores)", \
       f using 1:4 with linespoints pt 5 title "fandisk topology only (measured, 2 host cores)", \
       f using 1:5 with linespoints pt 9 title "blade3 geometric (measured, 2 host cores)", \
       f using 1:6 with linespoints pt 11 title "blade3 topology only (measured, 2 host cores)", \
       f using 1:7 with linespoints pt 13 dashtype 3 title "blade3 geometric, --min-angle 1 (measured, 2 host cores)"
}
