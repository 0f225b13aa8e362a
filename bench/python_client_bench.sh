#!/usr/bin/env bash
# The Python client's end-to-end time against the C++ client's, same server, same job, runs
# interleaved (docs/BENCHMARKS.md, "Python client"). Each run reads IN, uploads it, waits for
# the server, downloads and writes the output: the whole command, interpreter start included.
#   bench/python_client_bench.sh [IN] [RUNS] [engine flags...]
# Default IN: /tmp/blade_loop3.ply (build/bench/make_meshes tests/data/blade.off /tmp/blade_loop 3).
set -euo pipefail
cd "$(dirname "$0")/.."
in=${1:-/tmp/blade_loop3.ply}
runs=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
flags=("$@")
[ ${#flags[@]} -gt 0 ] || flags=(--ratio 0.5 --max-passes 2)
out=$(mktemp -d)
log=$out/server.log
build/server/femsimp-server --listen=127.0.0.1:0 --metrics_listen= --workers=1 2>"$log" &
server=$!
trap 'kill $server 2>/dev/null; wait $server 2>/dev/null; rm -rf "$out"' EXIT
for _ in $(seq 100); do grep -q "(port " "$log" && break; sleep 0.1; done
address=127.0.0.1:$(sed -n 's/.*listening on [^ ]* (port \([0-9]*\)).*/\1/p' "$log" | head -1)
ext=${in##*.}
# Wall seconds and the client process's own CPU seconds (user + system): the CPU figure is what
# the client costs, free of the server's time and of other load on the machine.
timed() { /usr/bin/time -f "%e %U %S" -o "$out/time" "$@" >/dev/null; awk '{print $1, $2 + $3}' "$out/time"; }
cpp=() py=() cpp_cpu=() py_cpu=()
for i in $(seq "$runs"); do
  read -r w c < <(timed build/client/femsimp simplify "$in" "$out/cpp.$ext" --server "$address" --quiet "${flags[@]}")
  cpp+=("$w") cpp_cpu+=("$c")
  read -r w c < <(timed env PYTHONPATH=python /usr/bin/python3 -W ignore -m femsimp simplify "$in" "$out/py.$ext" --server "$address" --quiet "${flags[@]}")
  py+=("$w") py_cpu+=("$c")
  echo "run $i: C++ ${cpp[-1]} s (client CPU ${cpp_cpu[-1]} s), Python ${py[-1]} s (client CPU ${py_cpu[-1]} s)"
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
c=$(median "${cpp[@]}") p=$(median "${py[@]}")
echo "$in, ${flags[*]}: median of $runs: C++ client $c s, Python client $p s, ratio $(echo "scale=3; $p / $c" | bc); client CPU C++ $(median "${cpp_cpu[@]}") s, Python $(median "${py_cpu[@]}") s"
