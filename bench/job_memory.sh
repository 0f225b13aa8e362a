#!/usr/bin/env bash
# Peak memory of one job on the server (docs/BENCHMARKS.md, "Memory per job"): starts a
# femsimp-server (one worker, one thread, no metrics) under /usr/bin/time -f %M on a free loopback
# port, sends MESH through `femsimp simplify` with the given flags, stops the server and prints
# its peak RSS in KiB. MESH `none` gives the idle server's.
#
#   bench/job_memory.sh MESH [femsimp simplify flags...]
# Environment: FEMSIMP_BUILD (default build).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${FEMSIMP_BUILD:-build}
mesh=$1
shift
work=$(mktemp -d /tmp/femsimp-job-memory.XXXXXX)
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
/usr/bin/time -f %M -o "$work/rss" "$build/server/femsimp-server" --listen "127.0.0.1:$port" \
  --metrics_listen= --workers 1 --threads_per_job 1 >"$work/server.log" 2>&1 &
time_pid=$!
trap 'kill "$time_pid" 2>/dev/null || true; rm -rf "$work"' EXIT
for _ in $(seq 1 100); do
  "$build/client/femsimp" health --server "127.0.0.1:$port" --timeout 1 >/dev/null 2>&1 && break
  sleep 0.1
done
if [ "$mesh" != none ]; then
  "$build/client/femsimp" simplify "$mesh" "$work/out.ply" --server "127.0.0.1:$port" --quiet \
    --threads 1 "$@" >/dev/null
fi
kill -TERM "$(pgrep -P "$time_pid" femsimp-server)"
wait "$time_pid"
echo "$(basename "$mesh") $* peak_rss_kib=$(cat "$work/rss")"
