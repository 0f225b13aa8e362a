#!/usr/bin/env bash
# One speed table (issue 14, item 5): builds speed_table, makes the benchmark meshes if missing
# (the Loop-subdivided blades at 3 and 4 levels, a gmsh CAD-like part), runs it on fandisk, the
# two blades and the part, and writes the table to BUILD_DIR/bench-results/speed_table.md and
# into its section of docs/BENCHMARKS.md (replaced; appended at the end when absent).
# Arguments go to speed_table (e.g. --repeats 5, --openmesh-all). Environment: BUILD_DIR
# (default build), JOBS (default 2).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
data=$root/bench/data
cad=$build/cad-meshes
part=$cad/bottle_fine.off # 22,959 vertices, 45,914 faces, open at the neck
results=$build/bench-results
doc=$root/docs/BENCHMARKS.md
heading="## One table: femsimp beside meshoptimizer and OpenMesh (issue 14, item 5)"

[[ -f $build/build.ninja ]] ||
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"${JOBS:-2}" --target make_meshes speed_table

mkdir -p "$data" "$results"
if [[ ! -f $data/blade_loop3.ply || ! -f $data/blade_loop4.ply ]]; then
  "$build/bench/make_meshes" "$root/tests/data/blade.off" "$data/blade_loop" 3 4
fi
# The CAD-like part: gmsh's OpenCASCADE kernel (scripts/make_cad_meshes.py, deterministic).
[[ -f $part ]] || /usr/bin/python3 "$root/scripts/make_cad_meshes.py" "$cad" --only bottle --quiet

"$build/bench/speed_table" "fandisk=$root/tests/data/fandisk.off" \
  "blade_loop3=$data/blade_loop3.ply" "blade_loop4=$data/blade_loop4.ply" \
  "bottle_fine=$part" --command "bench/speed_table.sh${*:+ $*}" "$@" >"$results/speed_table.md"

# The section holds the latest table: everything from its heading to the next section's.
python3 - "$doc" "$heading" "$results/speed_table.md" <<'PY'
import sys
doc, heading, table = sys.argv[1], sys.argv[2], open(sys.argv[3]).read()
lines = open(doc).read().split("\n")
section = [heading, "", table.rstrip("\n"), ""]
if heading in lines:
    start = lines.index(heading)
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    lines[start:end] = section
else:
    while lines and lines[-1] == "":
        lines.pop()
    lines += [""] + section
open(doc, "w").write("\n".join(lines).rstrip("\n") + "\n")
PY
echo "wrote $results/speed_table.md and its section of $doc"
