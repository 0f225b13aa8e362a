#!/usr/bin/env bash
# Keeps what fuzz runs found: merges each target's corpus (BUILD/corpus/<target>, fuzz/run.sh)
# into the kept one (BUILD/fuzz/corpus/<target>, from fuzz/corpus.tar.xz), keeping only inputs
# that add coverage (libFuzzer -merge=1), and writes fuzz/corpus.tar.xz again. Commit it: the
# replay tests (ctest -L fuzz) and later runs start from it.
#
#   fuzz/keep-corpus.sh [BUILD]   # default build-fuzz, a FEMSIMP_FUZZ=ON build
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for t in off obj stl_ascii stl_binary ply msh request; do
  mkdir -p "$work/corpus/$t"
  inputs=()
  for d in "$build/fuzz/corpus/$t" "$build/corpus/$t"; do [ -d "$d" ] && inputs+=("$d"); done
  "$build/fuzz/${t}_fuzzer" -merge=1 -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
    "$work/corpus/$t" "${inputs[@]}" >"$work/$t.log" 2>&1 || { cat "$work/$t.log"; exit 1; }
  echo "$t: $(find "$work/corpus/$t" -type f | wc -l) inputs"
done
tar -C "$work" -cJf fuzz/corpus.tar.xz corpus
echo "wrote fuzz/corpus.tar.xz ($(du -h fuzz/corpus.tar.xz | cut -f1))"
