#!/usr/bin/env bash
# Installs the Debian 12 packages femsimp builds, tests and benchmarks with (only what is missing).
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config clang-format
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler libabsl-dev
  prometheus-cpp-dev libopenmesh-dev libgtest-dev libgmock-dev libbenchmark-dev
  libmeshoptimizer-dev libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev
  python3-grpcio grpc-proto curl tetgen gnuplot-nox nginx-light python3-gmsh python3-numpy
  python3-protobuf python3-meshio python3-pytest  # the Python client (python/) and its tests
  calculix-ccx  # femsimp check and --fe-check (with tetgen): the CalculiX solver, ccx
  gdb  # scripts/watchdog.sh prints a hung test's stacks
  clang libclang-rt-14-dev  # the fuzz targets (libFuzzer, ASan, UBSan)
)
# The deployment checks (tests/deploy) only read and render configs, so without the packages
# these recommend (prometheus-node-exporter, ...). The container test (deploy/test-container.sh)
# starts Debian's Docker daemon by hand (docker.io: its own daemon, apart from the one the
# package starts where systemd runs) and makes its Debian base image with debootstrap (no
# registry needed). Debian's kubectl
# (kubernetes-client) conflicts with other kubectl packages, so only when there is none.
deploy_packages=(python3-kubernetes python3-yaml prometheus docker-compose docker.io debootstrap)
command -v kubectl >/dev/null || deploy_packages+=(kubernetes-client)

missing_of() {
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}
mapfile -t missing < <(missing_of "${packages[@]}")
mapfile -t missing_deploy < <(missing_of "${deploy_packages[@]}")
if ((${#missing[@]} + ${#missing_deploy[@]})); then
  echo "installing: ${missing[*]} ${missing_deploy[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -qq
  if ((${#missing[@]})); then
    $sudo_cmd apt-get install -y -qq -o DPkg::Lock::Timeout=600 "${missing[@]}"
  fi
  if ((${#missing_deploy[@]})); then
    $sudo_cmd apt-get install -y -qq -o DPkg::Lock::Timeout=600 --no-install-recommends \
      "${missing_deploy[@]}"
  fi
fi
