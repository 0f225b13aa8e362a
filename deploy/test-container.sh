#!/usr/bin/env bash
# Container test: starts Debian's Docker daemon by hand (its own data and exec roots in a
# temporary folder, no bridge, no iptables or forwarding changes), builds deploy/Dockerfile, runs
# the image with host networking on free loopback ports, and checks it: non-root, the server is
# PID 1, health SERVING over TLS (femsimp health from the host and Docker's own HEALTHCHECK),
# plaintext and token-less calls refused, fandisk simplified through it with the host's client,
# verified jobs, /metrics, and a SIGTERM stop that
# exits 0 well before Docker would SIGKILL; then builds the compose stack's nginx and Prometheus
# images and checks their configs inside them. Reports the build time and image size. Stops and
# removes everything it started (containers, images, daemon, mounts) on any exit.
#
#   deploy/test-container.sh
#
# Without Docker Hub (as here), the Debian base image is made with debootstrap from the Debian
# archive and cached as a tarball in FEMSIMP_IMAGE_CACHE (default /var/tmp/femsimp-image-cache).
# Environment: FEMSIMP_BUILD (host build with the client, default build), FEMSIMP_CONTAINER_TEST
# (auto: skip when no engine can start; 1: fail instead of skipping; 0: skip), DEBIAN_MIRROR.
# Exit codes: 0 passed, 1 failed, 77 skipped.
set -euo pipefail
cd "$(dirname "$0")/.."

build=${FEMSIMP_BUILD:-build}
mode=${FEMSIMP_CONTAINER_TEST:-auto}
cache=${FEMSIMP_IMAGE_CACHE:-/var/tmp/femsimp-image-cache}
mirror=${DEBIAN_MIRROR:-http://deb.debian.org/debian}
image=femsimp:test
lb_image=femsimp-lb:test
prom_image=femsimp-prometheus:test
base_tag=femsimp-test/debian:bookworm-minbase

skip() {
  if [ "$mode" = 1 ]; then
    echo "test-container: FAILED: $*" >&2
    exit 1
  fi
  echo "test-container: SKIP: $*"
  exit 77
}
[ "$mode" = 0 ] && skip "FEMSIMP_CONTAINER_TEST=0"
[ "$(id -u)" -eq 0 ] || skip "starting dockerd needs root"
command -v dockerd >/dev/null || skip "no dockerd (Debian: docker.io)"
# Debian's client matches its daemon; another docker on PATH may want buildx.
docker_cli=/usr/bin/docker
[ -x "$docker_cli" ] || docker_cli=$(command -v docker) || skip "no docker client"
client_bin=$build/client/femsimp
load_bin=$build/client/femsimp-load
for b in "$client_bin" "$load_bin"; do
  [ -x "$b" ] || { echo "test-container: $b not built" >&2; exit 1; }
done

work=$(mktemp -d /tmp/femsimp-container.XXXXXX)
sock=$work/docker.sock
dockerd_pid=""
daemon_children=""
container=""

D() { DOCKER_HOST="unix://$sock" DOCKER_BUILDKIT=0 "$docker_cli" "$@"; }

stop_pid() {  # stop_pid PID SECONDS: SIGTERM, then SIGKILL after SECONDS
  local pid=$1
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 1 $((10 * $2))); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
}

cleanup() {
  local rc=$?
  set +e
  if [ -n "$dockerd_pid" ] && kill -0 "$dockerd_pid" 2>/dev/null; then
    if [ "$rc" -ne 0 ] && [ -n "$container" ]; then
      echo "--- container log (last 20 lines)"
      D logs --tail 20 "$container" 2>&1
    fi
    local ids
    ids=$(D ps -aq 2>/dev/null)
    [ -n "$ids" ] && D rm -f $ids >/dev/null 2>&1
    D rmi -f "$image" "$lb_image" "$prom_image" "$base_tag" >/dev/null 2>&1
    daemon_children=$(pgrep -P "$dockerd_pid" | tr '\n' ' ')
  fi
  stop_pid "$dockerd_pid" 30
  for pid in $daemon_children; do stop_pid "$pid" 10; done  # its containerd
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    for f in "$work"/dockerd.log "$work"/build.log; do
      [ -f "$f" ] && { echo "--- $f (last 20 lines)"; tail -n 20 "$f"; }
    done
  fi
  # Mounts the daemon left behind (it normally removes them), innermost first.
  awk -v w="$work" 'index($2, w) == 1 { print $2 }' /proc/mounts | sort -r |
    while read -r m; do umount -l "$m"; done
  rm -rf "$work"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

check() {  # check DESCRIPTION COMMAND...: runs it, fails the test when it fails
  local what=$1
  shift
  if "$@"; then
    echo "ok: $what"
  else
    echo "test-container: FAILED: $what" >&2
    exit 1
  fi
}

# --- the daemon: host networking only, so no bridge and no firewall or sysctl changes.
dockerd --data-root "$work/data" --exec-root "$work/exec" -H "unix://$sock" \
  --pidfile "$work/dockerd.pid" --bridge=none --iptables=false --ip-forward=false \
  --ip-masq=false --userland-proxy=false >"$work/dockerd.log" 2>&1 &
dockerd_pid=$!
for _ in $(seq 1 300); do
  D version >/dev/null 2>&1 && break
  kill -0 "$dockerd_pid" 2>/dev/null || break
  sleep 0.2
done
D version >/dev/null 2>&1 || skip "dockerd did not start (see its log above)"
echo "dockerd $(D version -f '{{.Server.Version}}') up (pid $dockerd_pid)"

# --- the base image: Docker Hub's when it can be pulled, else debootstrap's (cached).
base=debian:bookworm-slim
if ! timeout 120 "$docker_cli" -H "unix://$sock" pull -q "$base" >/dev/null 2>&1; then
  tarball=$cache/debian-bookworm-minbase.tar
  if [ ! -s "$tarball" ]; then
    command -v debootstrap >/dev/null || skip "cannot pull $base and no debootstrap to make one"
    echo "no registry: making a Debian 12 base image with debootstrap (once, cached in $cache)"
    rootfs=$work/rootfs
    debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$work/debootstrap.log" 2>&1 ||
      { tail -n 20 "$work/debootstrap.log"; exit 1; }
    cat >"$rootfs/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
deb ${mirror%/debian}/debian-security bookworm-security main
EOF
    # As in the official slim images: no documentation, manuals or translations get installed.
    cat >"$rootfs/etc/dpkg/dpkg.cfg.d/slim" <<'EOF'
path-exclude /usr/share/doc/*
path-include /usr/share/doc/*/copyright
path-exclude /usr/share/man/*
path-exclude /usr/share/info/*
path-exclude /usr/share/locale/*
path-exclude /usr/share/lintian/*
EOF
    find "$rootfs/usr/share/doc" -mindepth 1 -not -name copyright -not -type d -delete
    rm -rf "$rootfs"/usr/share/{man,info,locale}/* "$rootfs"/var/cache/apt/archives/*.deb \
      "$rootfs"/var/lib/apt/lists/*
    mkdir -p "$cache"
    tar -C "$rootfs" -cf "$tarball.tmp" . && mv "$tarball.tmp" "$tarball"
    rm -rf "$rootfs"
  fi
  D import "$tarball" "$base_tag" >/dev/null
  base=$base_tag
fi
base_bytes=$(D image inspect -f '{{.Size}}' "$base")

# --- build (the build stage installs from the Debian archive over the host's network).
t0=$(date +%s.%N)
D build --network host -f deploy/Dockerfile --build-arg "DEBIAN_IMAGE=$base" -t "$image" . \
  >"$work/build.log" 2>&1 || { echo "docker build failed" >&2; exit 1; }
build_seconds=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
image_bytes=$(D image inspect -f '{{.Size}}' "$image")

# --- run it on free loopback ports, host networking.
read -r grpc_port metrics_port < <(/usr/bin/python3 -c '
import socket
a, b = socket.socket(), socket.socket()
a.bind(("127.0.0.1", 0)); b.bind(("127.0.0.1", 0))
print(a.getsockname()[1], b.getsockname()[1])')
addr=127.0.0.1:$grpc_port
# As deployed: TLS and tokens from files in /run/secrets (each file mounted, as compose does).
deploy/make-dev-secrets.sh "$work/secrets" >/dev/null
secret_mounts=()
for f in server.pem server.key ca.pem tokens.csv; do
  secret_mounts+=(-v "$work/secrets/$f:/run/secrets/$f:ro")
done
tls=(--tls-ca-file "$work/secrets/ca.pem")
auth=("${tls[@]}" --token-file "$work/secrets/token-dev")
container=$(D run -d --name "femsimp-test-$$" --network host -e "FEMSIMP_HEALTH_ADDR=$addr" \
  "${secret_mounts[@]}" "$image" --listen="$addr" --tls_cert_file=/run/secrets/server.pem \
  --tls_key_file=/run/secrets/server.key --auth_tokens_file=/run/secrets/tokens.csv \
  --metrics_listen="127.0.0.1:$metrics_port" --workers=2 --threads_per_job=1 \
  --grace_period_seconds=10)

serving() {
  for _ in $(seq 1 300); do
    "$client_bin" health --server "$addr" "${tls[@]}" --timeout 1 >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  return 1
}
check "health SERVING over TLS from the host (femsimp health --server $addr)" serving
check "a plaintext call is refused" sh -c "! '$client_bin' health --server '$addr' --timeout 2"
check "a call without a token is refused" sh -c "! '$client_bin' simplify tests/data/fandisk.off \
  '$work/no-token.off' --server '$addr' --tls-ca-file '$work/secrets/ca.pem' --max-attempts 1"
check "runs as uid 10001, not root" test "$(D exec "$container" id -u)" = 10001
check "femsimp-server is PID 1" \
  test "$(D exec "$container" cat /proc/1/cmdline | tr '\0' ' ' | cut -d' ' -f1)" = \
  /usr/local/bin/femsimp-server
check "the image's probe works inside it" D exec "$container" /usr/local/bin/femsimp health \
  --server "$addr" --tls-ca-file /run/secrets/ca.pem --service femsimp.v1.Simplifier

"$client_bin" simplify tests/data/fandisk.off "$work/fandisk-out.off" --server "$addr" "${auth[@]}" \
  --ratio 0.3 --quiet --stats-json "$work/fandisk.json"
out_vertices=$(/usr/bin/python3 -c \
  'import json,sys; print(json.load(open(sys.argv[1]))["output"]["vertices"])' "$work/fandisk.json")
check "fandisk simplified through the container (6475 -> $out_vertices vertices)" \
  test "$out_vertices" -gt 0 -a "$out_vertices" -lt 6475 -a -s "$work/fandisk-out.off"
check "20 jobs through the container, outputs verified" "$load_bin" --server "$addr" "${auth[@]}" \
  --clients 2 --jobs 20 --verify tests/data/fandisk.off tests/data/femur.off

metrics=$(curl -sf "http://127.0.0.1:$metrics_port/metrics")
ok_jobs=$(awk '$1 ~ /^femsimp_jobs_total\{/ && $1 ~ /status="OK"/ { s += $2 } END { print s + 0 }' \
  <<<"$metrics")
check "/metrics counts the 21 jobs (femsimp_jobs_total{status=\"OK\",tenant=\"dev\"} = ${ok_jobs:-none})" \
  test "${ok_jobs:-0}" -eq 21

healthy() {
  for _ in $(seq 1 60); do
    [ "$(D inspect -f '{{.State.Health.Status}}' "$container")" = healthy ] && return 0
    sleep 1
  done
  return 1
}
check "Docker's HEALTHCHECK reports healthy" healthy

t_stop=$(date +%s.%N)
D stop -t 30 "$container" >/dev/null
stop_seconds=$(awk -v a="$t_stop" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
check "SIGTERM stop exits 0 (after $stop_seconds s, not Docker's SIGKILL at 30 s)" \
  test "$(D inspect -f '{{.State.ExitCode}}' "$container")" = 0
check "the server logged the SIGTERM and a clean stop" \
  sh -c "DOCKER_HOST=unix://$sock $docker_cli logs $container 2>&1 | grep -q 'SIGTERM received' &&
         DOCKER_HOST=unix://$sock $docker_cli logs $container 2>&1 | grep -q 'stopped'"

# The compose stack's other two images build from the same base, and their configs pass their
# own checks inside them (the stack itself needs a bridge network, which these machines keep out).
D build --network host --build-arg "DEBIAN_IMAGE=$base" -t "$lb_image" deploy/nginx \
  >>"$work/build.log" 2>&1 || { echo "docker build deploy/nginx failed" >&2; exit 1; }
check "the compose stack's nginx image accepts its config" D run --rm --network none \
  --add-host femsimp:127.0.0.1 "${secret_mounts[@]}" "$lb_image" -t -c /etc/nginx/nginx.conf
D build --network host --build-arg "DEBIAN_IMAGE=$base" -t "$prom_image" deploy/prometheus \
  >>"$work/build.log" 2>&1 || { echo "docker build deploy/prometheus failed" >&2; exit 1; }
check "the compose stack's Prometheus image accepts its config and rules" D run --rm \
  --network none --entrypoint /usr/bin/promtool "$prom_image" check config \
  /etc/prometheus/prometheus.yml

awk -v i="$image" -v ib="$image_bytes" -v b="$base" -v bb="$base_bytes" -v s="$build_seconds" \
  'BEGIN { printf "image %s: %.1f MB (base %s %.1f MB, femsimp layers %.1f MB), build %.0f s\n",
           i, ib / 1e6, b, bb / 1e6, (ib - bb) / 1e6, s }'
echo "test-container: PASSED"
