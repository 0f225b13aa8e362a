#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through ctest (the deployment tests,
# label deploy, included); then the engine and cellsim tests again under ThreadSanitizer; then
# the mesh readers under libFuzzer (ASan, UBSan); then the container test where a Docker daemon
# can be started. Fails when any test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
jobs=$(nproc)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"
# No reruns: a test that fails once is a bug to find.
ctest --test-dir build --output-on-failure --no-tests=error -j "$jobs"
cmake -S . -B build-tsan -G Ninja -DFEMSIMP_TSAN=ON
cmake --build build-tsan -j "$jobs"
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
  ctest --test-dir build-tsan --output-on-failure --no-tests=error -j "$jobs" -L tsan
# The mesh readers under libFuzzer with AddressSanitizer and UndefinedBehaviorSanitizer (clang;
# fuzz/): a minute from the seeds in fuzz/seeds; a crash fails the run and leaves its input in
# build-fuzz/.
cmake -S . -B build-fuzz -G Ninja -DFEMSIMP_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++
cmake --build build-fuzz -j "$jobs"
mkdir -p build-fuzz/corpus
build-fuzz/fuzz/mesh_reader_fuzzer -max_total_time=60 -max_len=4096 -rss_limit_mb=2048 \
  -timeout=10 -print_final_stats=1 -artifact_prefix=build-fuzz/ build-fuzz/corpus fuzz/seeds
# The container image (deploy/test-container.sh) needs a Docker daemon it can start: Debian's
# docker.io and root. Without one it skips itself (77), as on a fresh CI machine;
# FEMSIMP_CONTAINER_TEST=0 skips it, =1 makes a missing engine a failure.
deploy/test-container.sh || [ $? -eq 77 ]
