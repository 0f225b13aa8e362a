#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through ctest (the deployment tests,
# label deploy, included); then the engine and cellsim tests again under ThreadSanitizer; then
# the container test where a Docker daemon can be started. Fails when any test fails.
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
# The container image (deploy/test-container.sh) needs a Docker daemon it can start: Debian's
# docker.io and root. Without one it skips itself (77), as on a fresh CI machine;
# FEMSIMP_CONTAINER_TEST=0 skips it, =1 makes a missing engine a failure.
deploy/test-container.sh || [ $? -eq 77 ]
