#!/usr/bin/env bash
# Quick start: install what is missing, build (Release), start femsimp-server on localhost,
# simplify tests/data/fandisk.off through it with per-pass progress, show some /metrics, stop.
set -euo pipefail
cd "$(dirname "$0")/.."

port=${FEMSIMP_PORT:-50051}
metrics_port=${FEMSIMP_METRICS_PORT:-9464}
jobs=${FEMSIMP_BUILD_JOBS:-$(nproc)}

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs" --target femsimp femsimp-server

mkdir -p out
server_pid=""
stop_server() {
  if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then
    kill -TERM "$server_pid"
    wait "$server_pid" || true
  fi
  server_pid=""
}
trap stop_server EXIT

build/server/femsimp-server --listen "127.0.0.1:$port" \
  --metrics_listen "127.0.0.1:$metrics_port" 2>out/femsimp-server.log &
server_pid=$!

# Ready once the metrics endpoint answers (the gRPC port is bound before it).
for _ in $(seq 1 50); do
  curl -sf "http://127.0.0.1:$metrics_port/metrics" >/dev/null && break
  kill -0 "$server_pid" 2>/dev/null || { cat out/femsimp-server.log; exit 1; }
  sleep 0.2
done

build/client/femsimp simplify tests/data/fandisk.off out/fandisk-simplified.off \
  --server "127.0.0.1:$port" --ratio 0.3 --stats-json out/fandisk-simplified.json

echo
echo "--- a few lines of http://127.0.0.1:$metrics_port/metrics"
curl -s "http://127.0.0.1:$metrics_port/metrics" |
  grep -E '^femsimp_(jobs_total|vertices_(in|out|removed)_total|parallel_speedup_last|passes_total|job_duration_seconds_(sum|count))' || true

stop_server
echo
echo "--- server log (out/femsimp-server.log)"
cat out/femsimp-server.log
