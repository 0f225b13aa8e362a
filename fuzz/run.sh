#!/usr/bin/env bash
# Runs the fuzz targets of a FEMSIMP_FUZZ=ON build (fuzz/CMakeLists.txt), each for SECONDS or
# until it has run RUNS inputs, from its seeds (fuzz/seeds/<target>), the kept corpus
# (fuzz/corpus.tar.xz, unpacked by CMake into BUILD/fuzz/corpus/<target>) and its own corpus
# (BUILD/corpus/<target>, kept between runs: what one run found, the next starts from), and
# prints per target: executions, seconds, executions per second, coverage (edges) and features,
# corpus size, peak RSS. A crash, a sanitizer report, a leak, a timeout (10 s for one input) or
# an out-of-memory (2 GiB) stops that target, leaves the input as BUILD/crash-* (timeout-*,
# oom-*, leak-*) and fails the run (exit 1) once every target has run.
#
#   fuzz/run.sh BUILD SECONDS [RUNS] [TARGET...]   # scripts/test.sh: fuzz/run.sh build-fuzz 20
#   FUZZ_PARALLEL=2 fuzz/run.sh build-fuzz 3600 1000000   # long runs: fuzz/run-long.sh
#
# TARGET: off obj stl_ascii stl_binary ply msh request (default: all). FUZZ_PARALLEL targets run
# at once (default 1). A fixed crash goes to fuzz/crashes/<target>/, which ctest replays.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$1
seconds=$2
runs=${3:-0}
shift $(($# < 3 ? $# : 3))
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(off obj stl_ascii stl_binary ply msh request)
parallel=${FUZZ_PARALLEL:-1}

run_one() {
  local t=$1 log=$build/fuzz-$1.log rc=0
  mkdir -p "$build/corpus/$t"
  "$build/fuzz/${t}_fuzzer" -max_total_time="$seconds" -runs="$((runs > 0 ? runs : -1))" \
    -max_len=8192 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/" "$build/corpus/$t" "fuzz/seeds/$t" "$build/fuzz/corpus/$t" \
    >"$log" 2>&1 || rc=$?
  local execs secs cov ft corp rss
  execs=$(awk '/stat::number_of_executed_units/ { print $2 }' "$log")
  secs=$(grep -o 'in [0-9]* second(s)' "$log" | tail -1 | awk '{ print $2 }')
  read -r cov ft corp < <(grep -E '^#[0-9]+' "$log" | tail -1 |
    sed -E 's/.*cov: ([0-9]+) ft: ([0-9]+) corp: ([0-9]+).*/\1 \2 \3/')
  rss=$(awk '/stat::peak_rss_mb/ { print $2 }' "$log")
  if [ "$rc" -eq 0 ]; then
    printf '%-11s %10s execs %6s s %8s/s  cov %5s  ft %6s  corpus %5s  rss %4s MB  crashes 0\n' \
      "$t" "${execs:-?}" "${secs:-?}" "$(( ${execs:-0} / (${secs:-1} > 0 ? ${secs:-1} : 1) ))" \
      "${cov:-?}" "${ft:-?}" "${corp:-?}" "${rss:-?}"
  else
    echo "$t: FAILED (exit $rc), last lines of $log:"
    tail -n 40 "$log"
    return 1
  fi
}
export -f run_one
export build seconds runs
failed=0
printf '%s\n' "${targets[@]}" | xargs -P "$parallel" -I{} bash -c 'run_one {}' || failed=1
exit "$failed"
