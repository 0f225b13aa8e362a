#!/usr/bin/env bash
# Scale-out test, no container engine needed: REPLICAS femsimp-server processes on loopback ports,
# nginx (grpc_pass, deploy/nginx/grpc-proxy.conf) in front of them, and femsimp-load sending JOBS
# fandisk and femur jobs (alternating) through nginx at RATE jobs/s, so that the run lasts about
# as long on a fast machine as here. When half of the jobs are done, `femsimp simplify` sends a
# long job (blade, subdivided twice) straight to one replica, which is then killed with SIGKILL
# while running it, and RESTART_AFTER seconds later started again. Passes when every job
# completed with a verified output (femsimp-load --verify), none was lost or reported twice, and
# the restarted replica took jobs again; the long job must succeed on the restarted replica after
# retries, and every call nginx saw cut must have been retried. Prints the load spread over the
# replicas from /metrics. Everything runs as deployed: TLS on every gRPC hop (client -> nginx ->
# replicas, certificates from deploy/make-dev-secrets.sh) and bearer tokens (--auth_tokens_file).
#
#   deploy/test-scaleout.sh [--bench]
#
# --bench first measures throughput without a kill: one replica behind nginx, then all REPLICAS,
# with the CPU each part used per job and how busy the machine was (needs GNU time).
# Environment: FEMSIMP_BUILD (default build), JOBS (1200), RATE (100), CLIENTS (6), REPLICAS (3),
# REPLICA_FLAGS (per-replica server flags), RESTART_AFTER (0.5 s), LOAD_TIMEOUT (300 s),
# MESHES (the load's meshes, default tests/data/fandisk.off tests/data/femur.off).
# Exit codes: 0 passed, 1 failed, 77 skipped (no nginx). Everything started is stopped by PID,
# also on failure or interruption.
set -euo pipefail
cd "$(dirname "$0")/.."

build=${FEMSIMP_BUILD:-build}
jobs=${JOBS:-1200}
rate=${RATE:-100}
clients=${CLIENTS:-6}
replicas=${REPLICAS:-3}
replica_flags=${REPLICA_FLAGS:---workers=1 --threads_per_job=1 --queue_capacity=16}
restart_after=${RESTART_AFTER:-0.5}
load_timeout=${LOAD_TIMEOUT:-300}
bench=0
[ "${1:-}" = "--bench" ] && bench=1

server_bin=$build/server/femsimp-server
client_bin=$build/client/femsimp
load_bin=$build/client/femsimp-load
read -r -a meshes <<<"${MESHES:-tests/data/fandisk.off tests/data/femur.off}"
for b in "$server_bin" "$client_bin" "$load_bin"; do
  [ -x "$b" ] || { echo "test-scaleout: $b not built (cmake --build $build)" >&2; exit 1; }
done
nginx_bin=$(command -v nginx || echo /usr/sbin/nginx)
if [ ! -x "$nginx_bin" ]; then
  echo "test-scaleout: SKIP: nginx not installed (Debian: nginx-light)"
  exit 77
fi

work=$(mktemp -d /tmp/femsimp-scaleout.XXXXXX)
secrets=$work/secrets
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
  stop_pid "${big_pid:-}"
  stop_pid "$nginx_pid"
  for pid in "${replica_pid[@]}"; do stop_pid "$pid"; done
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    for f in "$work"/*.log; do
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

deploy/make-dev-secrets.sh "$secrets" >/dev/null
# What every client call carries: the CA that signed the servers' (and nginx's) certificate, and
# the tenant's token.
tls=(--tls-ca-file "$secrets/ca.pem")
auth=("${tls[@]}" --token-file "$secrets/token-dev")

read -r -a ports <<<"$(free_ports $((2 * replicas + 1)))"
lb_port=${ports[0]}
for ((i = 0; i < replicas; i++)); do
  grpc_port[i]=${ports[1 + 2 * i]}
  metrics_port[i]=${ports[2 + 2 * i]}
done

wait_healthy() {  # wait_healthy HOST:PORT SECONDS
  local deadline=$((SECONDS + $2))
  while ((SECONDS < deadline)); do
    "$client_bin" health --server "$1" "${tls[@]}" --timeout 1 >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  return 1
}

start_replica() {  # start_replica I
  local i=$1
  # shellcheck disable=SC2086  # REPLICA_FLAGS is a list of flags
  "$server_bin" --listen="127.0.0.1:${grpc_port[i]}" \
    --metrics_listen="127.0.0.1:${metrics_port[i]}" --grace_period_seconds=5 \
    --tls_cert_file="$secrets/server.pem" --tls_key_file="$secrets/server.key" \
    --auth_tokens_file="$secrets/tokens.csv" $replica_flags \
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
    listen 127.0.0.1:$lb_port ssl http2;
    ssl_certificate $secrets/server.pem;
    ssl_certificate_key $secrets/server.key;
    location / {
      include $PWD/deploy/nginx/grpc-proxy.conf;
      grpc_ssl_trusted_certificate $secrets/ca.pem;
    }
  }
}
EOF
  "$nginx_bin" -p "$work/nginx" -c "$work/nginx.conf" >>"$work/nginx.log" 2>&1 &
  nginx_pid=$!
  wait_healthy "127.0.0.1:$lb_port" 30 || { fail "nginx did not pass health checks through"; exit 1; }
}

ok_jobs() {  # ok_jobs I: jobs replica I finished OK (every tenant), 0 when unreachable
  curl -sf --max-time 2 "http://127.0.0.1:${metrics_port[$1]}/metrics" 2>/dev/null |
    awk '$1 ~ /^femsimp_jobs_total\{/ && $1 ~ /status="OK"/ { s += $2 } END { print s + 0 }'
}
jobs_seen() {  # jobs_seen I: jobs the replica finished, any status
  curl -sf --max-time 2 "http://127.0.0.1:${metrics_port[$1]}/metrics" 2>/dev/null |
    awk '$1 ~ /^femsimp_jobs_total\{/ { s += $2 } END { print s + 0 }'
}

run_load() {  # run_load OUT.json [extra femsimp-load flags]: in the background, pid in load_pid
  local out=$1
  shift
  timeout --signal=KILL "$load_timeout" "$load_bin" --server "127.0.0.1:$lb_port" "${auth[@]}" \
    --clients "$clients" --jobs "$jobs" --ratio 0.5 --json "$@" "${meshes[@]}" \
    >"$out" 2>>"$work/load.log" &
  load_pid=$!
}


# CPU seconds (user + system, all threads) of processes still running.
cpu_of() {
  local hz
  hz=$(getconf CLK_TCK)
  for p in "$@"; do awk '{ print $14 + $15 }' "/proc/$p/stat" 2>/dev/null || true; done |
    awk -v hz="$hz" '{ s += $1 } END { printf "%.2f", s / hz }'
}
machine_ticks() { awk '/^cpu / { print $2 + $3 + $4 + $7 + $8, $5 + $6 }' /proc/stat; }

bench_run() {  # bench_run N: nginx over the first N replicas (running), one load; one line
  local n=$1 busy0 idle0 busy1 idle1 servers0 nginx0 pids=()
  start_nginx "$n"
  for ((i = 0; i < n; i++)); do pids+=("${replica_pid[i]}"); done
  read -r busy0 idle0 < <(machine_ticks)
  servers0=$(cpu_of "${pids[@]}")
  # shellcheck disable=SC2046  # one PID a word
  nginx0=$(cpu_of "$nginx_pid" $(pgrep -P "$nginx_pid"))
  local time_file=$work/bench$n.time
  timeout --signal=KILL "$load_timeout" /usr/bin/time -f "%U %S" -o "$time_file" "$load_bin" \
    --server "127.0.0.1:$lb_port" "${auth[@]}" --clients "$clients" --jobs "$jobs" --ratio 0.5 --json \
    "${meshes[@]}" >"$work/bench$n.json" 2>>"$work/load.log" || fail "bench with $n replicas"
  read -r busy1 idle1 < <(machine_ticks)
  local servers nginx_cpu
  servers=$(awk -v a="$servers0" -v b="$(cpu_of "${pids[@]}")" 'BEGIN { printf "%.2f", b - a }')
  # shellcheck disable=SC2046
  nginx_cpu=$(awk -v a="$nginx0" -v b="$(cpu_of "$nginx_pid" $(pgrep -P "$nginx_pid"))" \
    'BEGIN { printf "%.2f", b - a }')
  stop_pid "$nginx_pid"
  nginx_pid=""
  /usr/bin/python3 - "$work/bench$n.json" "$time_file" "$n" "$servers" "$nginx_cpu" \
    "$((busy1 - busy0))" "$((idle1 - idle0))" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
client = sum(float(x) for x in open(sys.argv[2]).read().split()[-2:])
n, servers, nginx = sys.argv[3], float(sys.argv[4]), float(sys.argv[5])
busy, idle = int(sys.argv[6]), int(sys.argv[7])
jobs = r["succeeded"]
print(f"{n} replica(s): {r['jobs_per_second']:.1f} jobs/s ({jobs} jobs, {r['wall_seconds']:.2f} s, "
      f"p50 {r['latency_seconds']['p50'] * 1e3:.0f} ms); CPU per job: servers "
      f"{servers / jobs * 1e3:.2f} ms, nginx {nginx / jobs * 1e3:.2f} ms, client "
      f"{client / jobs * 1e3:.2f} ms; machine busy {100 * busy / max(1, busy + idle):.0f} %")
EOF
}

if ((bench)); then
  echo "== bench: $jobs jobs, $clients clients, replica flags: $replica_flags, $(nproc) cores"
  for ((i = 0; i < replicas; i++)); do start_replica "$i"; done
  bench_run 1
  bench_run "$replicas"
  for ((i = 0; i < replicas; i++)); do stop_pid "${replica_pid[i]}"; done
  replica_pid=()
  # The kill test below starts everything afresh (new logs, counters from zero).
  rm -f "$work"/replica-*.log "$work/nginx.log"
fi

echo "== scale-out: $replicas replicas behind nginx 127.0.0.1:$lb_port, $jobs jobs" \
  "(${meshes[*]##*/}), $clients clients"
for ((i = 0; i < replicas; i++)); do start_replica "$i"; done
start_nginx "$replicas"
# Through nginx, a call without a token, or in plaintext, must be refused (by the replica, by nginx).
"$client_bin" simplify tests/data/fandisk.off "$work/no-token.off" --server "127.0.0.1:$lb_port" \
  "${tls[@]}" --max-attempts 1 >"$work/no-token.log" 2>&1 && fail "a call without a token succeeded"
grep -q UNAUTHENTICATED "$work/no-token.log" || fail "no UNAUTHENTICATED without a token: $(cat "$work/no-token.log")"
FEMSIMP_TOKEN_FILE="$secrets/token-dev" "$client_bin" health --server "127.0.0.1:$lb_port" \
  --timeout 2 >/dev/null 2>&1 && fail "nginx answered a plaintext call"
echo "through nginx: TLS; a call without a token gets UNAUTHENTICATED, a plaintext one fails"

victim=$((replicas > 1 ? 1 : 0))
big_pid=""
big_mesh=""
if [ -x "$build/bench/make_meshes" ]; then
  # blade.off Loop-subdivided twice: 130,256 vertices, 259,552 faces.
  "$build/bench/make_meshes" tests/data/blade.off "$work/blade" 2 >/dev/null && big_mesh=$work/blade2.ply
fi
# Paced: the restarted replica must have time to rejoin (nginx retries it after 1 s) however
# fast the machine.
run_load "$work/load.json" --rate "$rate" --verify --max-attempts 8 --jobs-report "$work/jobs.tsv"
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
    # Half done: a long job straight to the victim (femsimp, as a client balancing by itself
    # would), so that the kill surely cuts a running job; nginx's jobs queue up behind it.
    if [ -n "$big_mesh" ]; then
      "$client_bin" simplify "$big_mesh" "$work/big-out.ply" "${auth[@]}" \
        --server "127.0.0.1:${grpc_port[victim]}" --ratio 0.2 --max-attempts 8 --deadline 240 --quiet --label long-job \
        --stats-json "$work/big.json" >"$work/big.log" 2>&1 &
      big_pid=$!
      # Until the victim's worker has started it (its log), however slow the machine is.
      for _ in $(seq 1 1200); do
        grep -q 'start: label="long-job"' "$work/replica-$victim.log" && break
        sleep 0.05
      done
      grep -q 'start: label="long-job"' "$work/replica-$victim.log" ||
        fail "the long job did not start on replica $victim within 60 s"
    fi
    victim_before=$(ok_jobs "$victim")
    kill -KILL "${replica_pid[victim]}"
    wait "${replica_pid[victim]}" 2>/dev/null || true
    killed=1
    echo "killed replica $victim (SIGKILL, pid ${replica_pid[victim]}) at $done_jobs jobs done," \
      "$((SECONDS - t0)) s in; it had finished $victim_before jobs"
    sleep "$restart_after"
    start_replica "$victim"
    restarted=1
    echo "restarted replica $victim (pid ${replica_pid[victim]}) $restart_after s later"
  fi
  sleep 0.1
done
load_rc=0
wait "$load_pid" || load_rc=$?
load_pid=""
if [ -n "$big_pid" ]; then
  big_rc=0
  wait "$big_pid" || big_rc=$?
  big_pid=""
  big_attempts=$(/usr/bin/python3 -c \
    'import json,sys; print(json.load(open(sys.argv[1]))["remote"]["attempts"])' "$work/big.json" \
    2>/dev/null || echo 0)
  echo "the long job sent straight to the killed replica: exit $big_rc after $big_attempts" \
    "attempts (femsimp retried until the replica was back)"
  grep 'femsimp: attempt' "$work/big.log" || true
  ((big_rc == 0)) || fail "the long job on the killed replica failed (exit $big_rc)"
  ((big_attempts >= 2)) || fail "the long job was not cut by the kill (attempts $big_attempts)"
  [ -s "$work/big-out.ply" ] || fail "the long job wrote no output"
fi

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
retried = [r for r in rows if int(r["attempts"]) > 1]
print(f"client: {len(rows)} jobs, each once, all OK and verified; {report['attempts']} attempts, "
      f"{report['retries']} retries ({len(retried)} jobs; failed attempts {report['failed_attempts']})")
for p in problems:
    print("test-scaleout: FAILED:", p, file=sys.stderr)
sys.exit(1 if problems else 0)
EOF

# Calls the kill cut (nginx had started relaying them) must each have been retried.
cut=$(grep -cE 'upstream prematurely closed|Connection reset by peer\) while reading' \
  "$work/nginx.log" || true)
retries=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["retries"])' \
  "$work/load.json")
echo "calls cut by the kill (nginx's log): $cut; client retries: $retries"
((retries >= cut)) || fail "$cut calls were cut but only $retries retried"

# The spread over the replicas, from their own /metrics (the killed one: before + after restart).
echo "load spread (femsimp_jobs_total{status=\"OK\"} per replica):"
total=0
for ((i = 0; i < replicas; i++)); do
  n=$(ok_jobs "$i")
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
