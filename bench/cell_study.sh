#!/usr/bin/env bash
# The cell back end's speedup study (paper: Fig. 5 and Table 1), as one command:
#
#   bench/cell_study.sh [--reuse] [--spes "1 2 4 8 16 32 64 128"] [--meshes "fandisk blade3"]
#
# 1. builds the femsimp CLI (Release) in build/ if it is missing;
# 2. makes bench/data/blade_loop3.ply (turbine blade, 3 Loop subdivisions, build/bench/make_meshes
#    as for the other benchmarks) if it is missing;
# 3. runs fandisk and blade3 with the default criteria (deterministic schedule), --topology-only,
#    and the default criteria with the paper's --schedule free, on 1..128 emulated SPEs, plus the
#    software-thread comparison (--spe-threads 1 vs 2, 64 KiB cache, 8 SPEs) and the native back
#    end at 1 thread; every run writes a --stats-json file under bench/data/cell_study/;
# 4. bench/cell_study.py turns the JSON files into markdown tables
#    (bench/data/cell_study/tables.md) and gnuplot data, and gnuplot draws
#    docs/cell-speedup.png (modeled) and docs/cell-speedup-measured.png (measured, 2 host cores).
#
# --reuse keeps JSON files of an earlier run instead of running them again.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build"
FEMSIMP="$BUILD/client/femsimp"
DATA="$ROOT/bench/data"
OUT="$DATA/cell_study"
REUSE=0
SPES="1 2 4 8 16 32 64 128"
MESHES="fandisk blade3"

while [[ $# -gt 0 ]]; do
  case "$1" in
    --reuse) REUSE=1; shift ;;
    --spes) SPES="$2"; shift 2 ;;
    --meshes) MESHES="$2"; shift 2 ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "cell_study.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

log() { printf '[cell_study %s] %s\n' "$(date +%H:%M:%S)" "$*" >&2; }

# 1. The CLI.
if [[ ! -x "$FEMSIMP" ]]; then
  log "building the femsimp CLI (Release) in $BUILD"
  if [[ ! -f "$BUILD/build.ninja" ]]; then
    cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DFEMSIMP_BUILD_SERVICE=ON -DFEMSIMP_BUILD_BENCH=OFF >&2
  fi
  ninja -C "$BUILD" -j"$(nproc)" femsimp >&2
fi
build_type="$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$BUILD/CMakeCache.txt" 2>/dev/null || true)"
[[ "$build_type" == "Release" ]] || log "warning: $BUILD is a '${build_type:-default}' build, not Release"

# 2. The 3-level Loop-subdivided blade (520,064 vertices, 1,038,208 faces).
mkdir -p "$DATA" "$OUT"
BLADE3="$DATA/blade_loop3.ply"
if [[ ! -f "$BLADE3" ]]; then
  log "subdividing tests/data/blade.off 3 times (Loop) -> $BLADE3"
  ninja -C "$BUILD" make_meshes >&2
  "$BUILD/bench/make_meshes" "$ROOT/tests/data/blade.off" "$DATA/blade_loop" 3 >&2
fi

mesh_path() {
  case "$1" in
    fandisk) echo "$ROOT/tests/data/fandisk.off" ;;
    blade3) echo "$BLADE3" ;;
    *) echo "cell_study.sh: unknown mesh '$1'" >&2; exit 2 ;;
  esac
}

# run NAME MESH ARGS...: one simplification, stats in $OUT/NAME.json.
run() {
  local name="$1" mesh="$2"; shift 2
  local json="$OUT/$name.json"
  if [[ $REUSE -eq 1 && -s "$json" ]]; then log "reuse $name"; return; fi
  local t0=$SECONDS
  "$FEMSIMP" simplify "$(mesh_path "$mesh")" "$OUT/mesh_out.off" --quiet \
    --stats-json "$json" "$@" >/dev/null
  log "$name done ($((SECONDS - t0)) s)"
}

# 3. The runs.
start=$SECONDS
for mesh in $MESHES; do
  # geo: the default criteria and schedule (deterministic rounds); topo: --topology-only;
  # free: the default criteria with the paper's free schedule (SPEs race for neighbourhoods).
  for crit in geo topo free; do
    extra=()
    [[ $crit == topo ]] && extra=(--topology-only)
    [[ $crit == free ]] && extra=(--schedule free)
    for n in $SPES; do
      run "${mesh}_${crit}_cell_s${n}" "$mesh" "${extra[@]}" --backend cell --spes "$n"
    done
    run "${mesh}_${crit}_native_t1" "$mesh" "${extra[@]}" --threads 1
  done
  for k in 1 2; do
    run "${mesh}_geo_cell_s8_c64_k${k}" "$mesh" --backend cell --spes 8 --ls-cache-kib 64 \
      --spe-threads "$k"
  done
done
rm -f "$OUT/mesh_out.off"
log "all runs done in $((SECONDS - start)) s"

# 4. Tables and plots.
{
  echo "machine: $(nproc) cores (nproc), $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)"
  echo "command: bench/cell_study.sh"
  echo "femsimp: $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown), build type ${build_type:-default}"
} >"$OUT/machine.txt"
/usr/bin/python3 "$ROOT/bench/cell_study.py" --dir "$OUT" --spes "$SPES" --meshes "$MESHES" \
  >"$OUT/tables.md"
cat "$OUT/machine.txt" "$OUT/tables.md"

if command -v gnuplot >/dev/null; then
  for kind in modeled measured; do
    suffix=""; [[ $kind == measured ]] && suffix="-measured"
    gnuplot -e "datadir='$OUT'; outfile='$ROOT/docs/cell-speedup$suffix.png'; kind='$kind'" \
      "$ROOT/bench/cell_study.gp"
  done
  log "wrote docs/cell-speedup.png and docs/cell-speedup-measured.png"
else
  log "gnuplot not found (apt-get install -y gnuplot-nox): no plots"
fi
