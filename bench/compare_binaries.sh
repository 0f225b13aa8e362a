#!/usr/bin/env bash
# Engine time of two femsimp binaries side by side: runs OLD and NEW alternately on MESH
# (REPEATS rounds at each thread count), reads engine_seconds from --stats-json, and prints
# the median of each and NEW/OLD. Alternating in one run keeps a loaded machine fair to both.
#   bench/compare_binaries.sh OLD NEW MESH [femsimp options...]
# Environment: REPEATS (default 7), THREADS (default "1 2").
set -euo pipefail
old=$1 new=$2 mesh=$3
shift 3
repeats=${REPEATS:-7}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
engine_seconds() {
  "$1" simplify "$mesh" "$work/out.ply" --quiet --stats-json "$work/s.json" "${@:2}" >/dev/null
  /usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["engine_seconds"])' \
    "$work/s.json"
}
echo "mesh: $mesh; options: $*; $repeats alternating rounds; load $(cut -d' ' -f1-3 /proc/loadavg)"
printf '| threads | old engine s (median) | new engine s (median) | new / old |\n|--:|--:|--:|--:|\n'
for t in ${THREADS:-1 2}; do
  : >"$work/old" && : >"$work/new"
  for ((r = 0; r < repeats; ++r)); do
    engine_seconds "$old" --threads "$t" "$@" >>"$work/old"
    engine_seconds "$new" --threads "$t" "$@" >>"$work/new"
  done
  o=$(median <"$work/old") n=$(median <"$work/new")
  printf '| %s | %.3f | %.3f | %.3f |\n' "$t" "$o" "$n" "$(echo "$n / $o" | bc -l)"
done
