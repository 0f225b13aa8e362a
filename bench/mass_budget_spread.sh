#!/usr/bin/env bash
# What the mass budgets cost in vertices, over several tolerances (docs/FIDELITY.md § 5): a
# greedy run decides a few per cent of its vertices either way, so one tolerance's ratio moves
# by up to 0.2 between two builds that differ in nothing that matters. For every mesh and every
# tolerance of TOLS, femsimp runs with --placement optimal without mass budgets and with the
# volume and inertia budgets; the table gives each mesh's ratios (budgets / none), and the last
# lines the geometric mean of all ratios, how many are within 1.1, and the vertex sums.
#   bench/mass_budget_spread.sh MESH...
# Environment: FEMSIMP (default build/client/femsimp), TOLS ("0.009 0.01 0.011"), VOLUME
# (0.001), INERTIA (0.005), JOBS (runs at once, default 2; each on 1 thread: the deterministic
# schedule's output does not depend on the thread count), OPTIONS (more femsimp options for
# every run, e.g. "--deviation-check measured --feature-angle 180").
set -euo pipefail
femsimp=${FEMSIMP:-build/client/femsimp}
tols=${TOLS:-0.009 0.01 0.011}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export femsimp work VOLUME=${VOLUME:-0.001} INERTIA=${INERTIA:-0.005} OPTIONS=${OPTIONS:-}
pair() {  # MESH TOL: one line "mesh tol vertices-without vertices-with"
  local id
  id=$(basename "$1").$2
  # shellcheck disable=SC2086
  "$femsimp" simplify "$1" "$work/$id.a.ply" --quiet --threads 1 --placement optimal \
    --tolerance-relative "$2" --max-volume-change 0 --stats-json "$work/$id.a.json" \
    $OPTIONS >/dev/null
  # shellcheck disable=SC2086
  "$femsimp" simplify "$1" "$work/$id.b.ply" --quiet --threads 1 --placement optimal \
    --tolerance-relative "$2" --max-volume-change "$VOLUME" --max-inertia-change "$INERTIA" \
    --stats-json "$work/$id.b.json" $OPTIONS >/dev/null
  /usr/bin/python3 -c 'import json, sys
a, b = (json.load(open(f))["output"]["vertices"] for f in sys.argv[3:5])
print(sys.argv[1], sys.argv[2], a, b)' "$(basename "$1")" "$2" "$work/$id.a.json" "$work/$id.b.json"
}
export -f pair
# shellcheck disable=SC2016  # $1 and $2 are the inner shell's
for mesh in "$@"; do
  for tol in $tols; do printf '%s\0%s\0' "$mesh" "$tol"; done
done | xargs -0 -n 2 -P "${JOBS:-2}" bash -c 'pair "$1" "$2"' _ >"$work/pairs.txt"
echo "placement optimal; budgets: volume $VOLUME, principal moments $INERTIA; tolerances: $tols;" \
  "options: ${OPTIONS:-none}"
/usr/bin/python3 - "$work/pairs.txt" "$tols" <<'PY'
import math, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
tols = sys.argv[2].split()
by_mesh = {}
for mesh, tol, free, kept in rows:
    by_mesh.setdefault(mesh, {})[tol] = (int(free), int(kept))
print("| mesh | " + " | ".join(f"{t}: V without / with budgets (ratio)" for t in tols) + " |")
print("|---|" + "---|" * len(tols))
ratios = []
for mesh in sorted(by_mesh):
    cells = []
    for t in tols:
        free, kept = by_mesh[mesh][t]
        ratios.append(kept / free)
        cells.append(f"{free} / {kept} ({kept / free:.2f})")
    print(f"| {mesh} | " + " | ".join(cells) + " |")
geo = math.exp(sum(map(math.log, ratios)) / len(ratios))
print(f"\n{len(ratios)} runs: geometric mean ratio {geo:.3f}; within 1.1: "
      f"{sum(r <= 1.1 for r in ratios)}; vertices without budgets "
      f"{sum(int(r[2]) for r in rows)}, with {sum(int(r[3]) for r in rows)}")
PY
