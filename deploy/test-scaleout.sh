#!/usr/bin/env bash
# Scale-out test, no container engine needed: REPLICAS femsimp-server processes on loopback ports,
# nginx (grpc_pass, deploy/nginx/grpc-proxy.conf) in front of them, and femsimp-load sending JOBS
# fandisk and femur jobs (alternating) through nginx. When half of the jobs are done one replica
# is killed with SIGKILL; at RESTART_AT of the jobs it is started again. Passes when every job
# completed with a verified output (femsimp-load --verify), none was lost or reported twice, and
# the restarted replica took jobs again. Prints the load spread over the replicas from /metrics.
#
#   deploy/test-scaleout.sh [--bench]
#
# --bench first measures throughput without a kill: one replica behind nginx, then all REPLICAS.
# Environment: FEMSIMP_BUILD (default build), JOBS (600), CLIENTS (6), REPLICAS (3),
# REPLICA_FLAGS (per-replica server flags), RESTART_AT (0.6), LOAD_TIMEOUT (300 s).
# Exit codes: 0 passed, 1 failed, 77 skipped (no nginx). Everything started is stopped by PID,
# also on failure or interruption.
set -euo pipefail
cd "$(dirname "$0")/.."

build=${FEMSIMP_BUILD:-build}
jobs=${JOBS:-600}
clients=${CLIENTS:-6}
replicas=${REPLICAS:-3}
replica_flags=${REPLICA_FLAGS:---workers=1 --threads_per_job=1 --queue_capacity=16}
restart_at=${RESTART_AT:-0.6}
load_timeout=${LOAD_TIMEOUT:-300}
bench=0
[ "${1:-}" = "--bench" ] && bench=1

server_bin=$build/server/femsimp-server
client_bin=$build/client/femsimp
load_bin=$build/client/femsimp-load
meshes=(tests/data/fandisk.off tests/data/femur.off)
for b in "$server_bin" "$client_bin" "$load_bin"; do
  [ -x "$b" ] || { echo "test-scaleout: $b not built (cmake --build $build)" >&2; exit 1; }
done
nginx_bin=$(command -v nginx || echo /usr/sbin/nginx)
if [ ! -x "$nginx_bin" ]; then
  echo "test-scaleout: SKIP: nginx not installed (Debian: nginx-light)"
  exit 77
fi

work=$(mktemp -d /tmp/femsimp-scaleout.XXXXXX)
declare -a replica_pid grpc_port metrics_port
nginx_pid=""
load_pid=""
failed=0

stop_pid() {  # stop_pid PID: SIGTERM, up to 15 s for a graceful exit, then SIGKILL
  local pid=$1
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 1 150); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
}

cleanup() {
  local rc=$?
  stop_pid "$load_pid"
  stop_pid "$nginx_pid"
  for pid in "${replica_pid[@]}"; do stop_pid "$pid"; done
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    for f in "$work"/*.log "$work"/load.out; do
      [ -f "$f" ] && { echo "--- $f (last 15 lines)"; tail -n 15 "$f"; }
    done
  fi
  rm -rf "$work"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

fail() {
  echo "test-scaleout: FAILED: $*" >&2
  failed=1
}

# Free loopback ports: bound to port 0 by the kernel, released just before use.
free_ports() {
  /usr/bin/python3 - "$1" <<'EOF'
import socket, sys
socks = []
for _ in range(int(sys.argv[1])):
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    socks.append(s)
print(" ".join(str(s.getsockname()[1]) for s in socks))
EOF
}

read -r -a ports <<<"$(free_ports $((2 * replicas + 1)))"
lb_port=${ports[0]}
for ((i = 0; i < replicas; i++)); do
  grpc_port[i]=${ports[1 + 2 * i]}
  metrics_port[i]=${ports[2 + 2 * i]}
done

wait_healthy() {  # wait_healthy HOST:PORT SECONDS
  local deadline=$((SECONDS + $2))
  while ((SECONDS < deadline)); do
    "$client_bin" health --server "$1" --timeout 1 >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  return 1
}

start_replica() {  # start_replica I
  local i=$1
  # shellcheck disable=SC2086  # REPLICA_FLAGS is a list of flags
  "$server_bin" --listen="127.0.0.1:${grpc_port[i]}" \
    --metrics_listen="127.0.0.1:${metrics_port[i]}" --grace_period_seconds=5 $replica_flags \
    >>"$work/replica-$i.log" 2>&1 &
  replica_pid[i]=$!
  wait_healthy "127.0.0.1:${grpc_port[i]}" 30 || { fail "replica $i did not become healthy"; exit 1; }
}

start_nginx() {  # start_nginx N: nginx in front of the first N replicas
  local n=$1 upstream=""
  for ((i = 0; i < n; i++)); do
    # A refused connection takes a replica out for 1 s, then nginx tries it again.
    upstream+="    server 127.0.0.1:${grpc_port[i]} max_fails=1 fail_timeout=1s;"$'\n'
  done
  mkdir -p "$work/nginx"
  cat >"$work/nginx.conf" <<EOF
daemon off;
worker_processes 1;
pid $work/nginx/nginx.pid;
error_log $work/nginx.log warn;
events { worker_connections 1024; }
http {
  access_log off;
  client_body_temp_path $work/nginx/body;
  proxy_temp_path $work/nginx/proxy;
  fastcgi_temp_path $work/nginx/fastcgi;
  uwsgi_temp_path $work/nginx/uwsgi;
  scgi_temp_path $work/nginx/scgi;
  upstream femsimp {
    least_conn;  # as in deploy/nginx/nginx.conf
$upstream  }
  server {
    listen 127.0.0.1:$lb_port http2;
    location / {
      include $PWD/deploy/nginx/grpc-proxy.conf;
    }
  }
}
EOF
  "$nginx_bin" -p "$work/nginx" -c "$work/nginx.conf" >>"$work/nginx.log" 2>&1 &
  nginx_pid=$!
  wait_healthy "127.0.0.1:$lb_port" 30 || { fail "nginx did not pass health checks through"; exit 1; }
}

metric() {  # metric I NAME: the sample's value on replica I, 0 when absent or unreachable
  curl -sf --max-time 2 "http://127.0.0.1:${metrics_port[$1]}/metrics" 2>/dev/null |
    awk -v n="$2" '$1 == n { v = $2 } END { print v + 0 }'
}
jobs_seen() {  # jobs_seen I: jobs the replica finished, any status
  curl -sf --max-time 2 "http://127.0.0.1:${metrics_port[$1]}/metrics" 2>/dev/null |
    awk '$1 ~ /^femsimp_jobs_total\{/ { s += $2 } END { print s + 0 }'
}

json_field() {  # json_field FILE KEY
  /usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"
}

run_load() {  # run_load OUT.json [extra femsimp-load flags]: in the background, pid in load_pid
  local out=$1
  shift
  timeout --signal=KILL "$load_timeout" "$load_bin" --server "127.0.0.1:$lb_port" \
    --clients "$clients" --jobs "$jobs" --ratio 0.5 --json "$@" "${meshes[@]}" \
    >"$out" 2>>"$work/load.log" &
  load_pid=$!
}

ok_metric='femsimp_jobs_total{status="OK"}'

if ((bench)); then
  echo "== bench: $jobs jobs, $clients clients, replica flags: $replica_flags, $(nproc) cores"
  start_replica 0
  start_nginx 1
  run_load "$work/bench1.json"
  wait "$load_pid" || fail "bench with 1 replica: femsimp-load failed"
  load_pid=""
  one=$(json_field "$work/bench1.json" jobs_per_second)
  stop_pid "$nginx_pid"
  nginx_pid=""
  for ((i = 1; i < replicas; i++)); do start_replica "$i"; done
  start_nginx "$replicas"
  run_load "$work/bench$replicas.json"
  wait "$load_pid" || fail "bench with $replicas replicas: femsimp-load failed"
  load_pid=""
  many=$(json_field "$work/bench$replicas.json" jobs_per_second)
  /usr/bin/python3 - "$one" "$many" "$replicas" <<'EOF'
import sys
one, many, n = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
print(f"throughput through nginx: 1 replica {one:.1f} jobs/s, {n} replicas {many:.1f} jobs/s, "
      f"ratio {many / one:.2f}")
EOF
  for ((i = 0; i < replicas; i++)); do stop_pid "${replica_pid[i]}"; done
  stop_pid "$nginx_pid"
  replica_pid=()
  nginx_pid=""
  # The kill test below starts everything afresh (new logs, counters from zero).
  rm -f "$work"/replica-*.log "$work/nginx.log"
fi

echo "== scale-out: $replicas replicas behind nginx 127.0.0.1:$lb_port, $jobs jobs" \
  "(${meshes[*]##*/}), $clients clients"
for ((i = 0; i < replicas; i++)); do start_replica "$i"; done
start_nginx "$replicas"

victim=$((replicas > 1 ? 1 : 0))
run_load "$work/load.json" --verify --max-attempts 8 --jobs-report "$work/jobs.tsv"
t0=$SECONDS
killed=0
restarted=0
victim_before=0
while kill -0 "$load_pid" 2>/dev/null; do
  done_jobs=$victim_before
  for ((i = 0; i < replicas; i++)); do
    if ((i != victim || killed == 0 || restarted == 1)); then
      done_jobs=$((done_jobs + $(jobs_seen "$i")))
    fi
  done
  if ((killed == 0 && 2 * done_jobs >= jobs)); then
    victim_before=$(metric "$victim" "$ok_metric")
    kill -KILL "${replica_pid[victim]}"
    wait "${replica_pid[victim]}" 2>/dev/null || true
    killed=1
    echo "killed replica $victim (SIGKILL, pid ${replica_pid[victim]}) at $done_jobs jobs done," \
      "$((SECONDS - t0)) s in; it had finished $victim_before jobs"
  elif ((killed == 1 && restarted == 0)) &&
    awk -v d="$done_jobs" -v j="$jobs" -v r="$restart_at" 'BEGIN { exit !(d >= r * j) }'; then
    start_replica "$victim"
    restarted=1
    echo "restarted replica $victim (pid ${replica_pid[victim]}) at $done_jobs jobs done"
  fi
  sleep 0.1
done
load_rc=0
wait "$load_pid" || load_rc=$?
load_pid=""

# What the client reports, and its per-job lines: every index once, every job OK.
cat "$work/load.json"
((load_rc == 0)) || fail "femsimp-load exited $load_rc (137: killed after $load_timeout s)"
((killed == 1 && restarted == 1)) || fail "the kill/restart did not happen (load ended too soon?)"
/usr/bin/python3 - "$work/load.json" "$work/jobs.tsv" "$jobs" <<'EOF' || failed=1
import collections, csv, json, sys
report, rows, jobs = json.load(open(sys.argv[1])), list(csv.DictReader(open(sys.argv[2]), delimiter="\t")), int(sys.argv[3])
problems = []
for key, want in (("jobs", jobs), ("succeeded", jobs), ("failed", 0), ("lost", 0), ("duplicates", 0), ("verified", True)):
    if report[key] != want:
        problems.append(f"report {key} = {report[key]}, expected {want}")
count = collections.Counter(int(r["index"]) for r in rows)
if sorted(count) != list(range(jobs)) or any(n != 1 for n in count.values()):
    problems.append(f"jobs report: {len(rows)} lines, indices not exactly 0..{jobs - 1} once each")
bad = [r for r in rows if r["status"] != "OK" or int(r["output_vertices"]) == 0]
if bad:
    problems.append(f"{len(bad)} jobs without a valid output, e.g. {bad[0]}")
processes = collections.Counter(r["job_id"].split("-")[0] for r in rows)
retried = [r for r in rows if int(r["attempts"]) > 1]
print(f"client: {len(rows)} jobs, each once, all OK and verified; {report['attempts']} attempts, "
      f"{report['retries']} retries ({len(retried)} jobs; failed attempts {report['failed_attempts']}); "
      f"results came from {len(processes)} server processes")
for p in problems:
    print("test-scaleout: FAILED:", p, file=sys.stderr)
sys.exit(1 if problems else 0)
EOF

# The spread over the replicas, from their own /metrics (the killed one: before + after restart).
echo "load spread (femsimp_jobs_total{status=\"OK\"} per replica):"
total=0
for ((i = 0; i < replicas; i++)); do
  n=$(metric "$i" "$ok_metric")
  n=${n%.*}
  if ((i == victim)); then
    before=${victim_before%.*}
    echo "  replica $i 127.0.0.1:${grpc_port[i]}: $before before the kill + $n after the restart"
    ((n >= 1)) || fail "the restarted replica took no job"
    ((before >= 1)) || fail "the victim had taken no job before the kill"
    n=$((n + before))
  else
    echo "  replica $i 127.0.0.1:${grpc_port[i]}: $n"
    ((n >= 1)) || fail "replica $i took no job"
  fi
  total=$((total + n))
done
echo "  servers finished $total jobs OK for the client's $jobs (more: a job done on a replica" \
  "whose result was cut by the kill, done again elsewhere; fewer: finished between the" \
  "last scrape and the kill)"

if ((failed)); then
  exit 1
fi
echo "test-scaleout: PASSED"
