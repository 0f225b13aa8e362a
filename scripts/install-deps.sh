#!/usr/bin/env bash
# Installs the Debian 12 packages femsimp builds, tests and benchmarks with (only what is missing).
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config clang-format
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler libabsl-dev
  prometheus-cpp-dev libopenmesh-dev libgtest-dev libgmock-dev libbenchmark-dev
  libmeshoptimizer-dev libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev
  python3-grpcio grpc-proto curl tetgen gnuplot-nox nginx-light
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -qq
  $sudo_cmd apt-get install -y -qq -o DPkg::Lock::Timeout=600 "${missing[@]}"
fi
