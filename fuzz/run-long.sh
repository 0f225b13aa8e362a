#!/usr/bin/env bash
# Long fuzz runs: builds the fuzz targets (build-fuzz, clang) and runs every one of them until it
# has run RUNS inputs (default 1,000,000) or SECONDS passed (default 3600), as many at once as
# there are cores, each from its seeds and the corpus earlier runs left in build-fuzz/corpus.
# Prints the figures per target (fuzz/run.sh); docs/ARCHITECTURE.md ("Fuzzing") keeps the last.
#
#   fuzz/run-long.sh [RUNS] [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-1000000}
seconds=${2:-3600}
shift $(($# < 2 ? $# : 2))
cmake -S . -B build-fuzz -G Ninja -DFEMSIMP_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build build-fuzz -j "$(nproc)"
FUZZ_PARALLEL=${FUZZ_PARALLEL:-$(nproc)} exec fuzz/run.sh build-fuzz "$seconds" "$runs" "$@"
