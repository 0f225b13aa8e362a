#!/usr/bin/env bash
# One command for the engine benchmark: builds (Release), makes the Loop-subdivided blades if
# missing, runs femsimp_bench on the 3-level blade (with peers), the 4-level blade (femsimp at
# 1 thread, for the linear-growth check) and fandisk, and writes its report to
# BUILD_DIR/bench-results/engine_report.md. (Its first run made the opening sections of
# docs/BENCHMARKS.md; the document has grown hand-written sections since, so the report no
# longer replaces it.)
# Environment: BUILD_DIR (default build), REPEATS (default 3), JOBS (default 2).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-bench}  # its own tree: it configures without the service
repeats=${REPEATS:-3}
data=$root/bench/data
results=$build/bench-results
report=$results/engine_report.md
started=$(date +%s)

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFEMSIMP_BUILD_SERVICE=OFF \
  -DFEMSIMP_BUILD_BENCH=ON >/dev/null
ninja -C "$build" -j"${JOBS:-2}" make_meshes femsimp_bench

mkdir -p "$data" "$results"
if [[ ! -f $data/blade_loop3.ply || ! -f $data/blade_loop4.ply ]]; then
  "$build/bench/make_meshes" "$root/tests/data/blade.off" "$data/blade_loop" 3 4 |
    tee "$results/make_meshes.log"
  grep -q "level=3 vertices=520064 faces=1038208" "$results/make_meshes.log"
  grep -q "level=4 vertices=2078336 faces=4152832" "$results/make_meshes.log"
fi

bench=$build/bench/femsimp_bench
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
# The 3-level blade: every peer, self-intersections checked (60 s limit each). --ratio: the
# min-angle-0 variant and topology-only stop at 10 % of the vertices (see the blade finding).
"$bench" "$data/blade_loop3.ply" --label="Blade, Loop-subdivided 3 levels" \
  --repeats="$repeats" --ratio=0.1 --json="$results/blade3.json" >"$results/blade3.md"
# The 4-level blade: femsimp at 1 thread only (engine time growth), no peers.
"$bench" "$data/blade_loop4.ply" --label="Blade, Loop-subdivided 4 levels (femsimp only)" \
  --repeats="$repeats" --ratio=0.1 --threads=1 --no-peers --si-timeout=0 \
  --json="$results/blade4.json" >"$results/blade4.md"
"$bench" "$root/tests/data/fandisk.off" --label="fandisk" --repeats="$repeats" \
  --json="$results/fandisk.json" >"$results/fandisk.md"
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

export BENCH_RESULTS=$results BENCH_LOAD_BEFORE=$load_before BENCH_LOAD_AFTER=$load_after \
  BENCH_REPEATS=$repeats BENCH_ELAPSED=$(($(date +%s) - started)) \
  BENCH_COMMIT=$(git -C "$root" rev-parse --short HEAD)
python3 "$root/bench/write_report.py" >"$report"
echo "wrote $report"
