#!/usr/bin/env bash
# Behaviour lock for refactors: simplifies every mesh in DATA under a fixed set of option sets
# at one thread (one SPE), where the engine is deterministic, and compares the sha256 of each
# output with the recorded one. Any change to what the engine decides shows up here.
#   check_outputs.sh FEMSIMP DATA HASHES            compare (exit 1 on any difference)
#   check_outputs.sh FEMSIMP DATA HASHES --update   record the current outputs
# A deliberate change of behaviour records new hashes in the same commit and says why. The
# sets recorded before the FE defaults run with --preset paper (the old defaults). The fe sets
# changed with the deterministic schedule (rounds, bucketed costs with scattered ties), and again
# when the deviation cost became the default order of tolerance runs, and every set changed when
# the inputs came to be renumbered in curve order before the build (engine/spatial_order.h: new
# ids, so new tie-breaks in the cost order and a new output numbering). The fe sets changed again
# when a collapse came to make the refused vertices of its fan candidates again (option
# periodic_retry off), and fidelity_budgets' blade when a pass that removed nothing left its
# untried vertices to a plain pass instead of reconsidering the same candidates again. The sets
# with a tolerance (every fe set, quadric_tolerance, fidelity_budgets, cell_1spe_fidelity)
# changed when the deviation bound came to sum displacement boxes instead of lengths (a tighter
# bound: more collapses pass it). femur's fe sets changed when the bound's cheap refusals came
# to run before Vd's ring is read (RuleStage::kScreen): a direction refused there is not also
# refused by a topology rule that reads beyond V's fan, so fewer refused vertices are retried.
set -euo pipefail
femsimp=$1 data=$2 hashes=$3 mode=${4:-check}
declare -A option_sets=(
  [defaults]="--preset paper"
  [topology_only]="--preset paper --topology-only --ratio 0.1"
  [quadric_tolerance]="--preset paper --cost quadric --tolerance-relative 0.01"
  [fidelity_budgets]="--preset paper --tolerance 0.002 --max-centroid-shift 0.002 --feature-angle 45 --min-angle 5 --max-normal-deviation 40 --max-field-change 0.02"
  [no_min_angle]="--preset paper --min-angle 0 --max-normal-deviation 40 --ratio 0.2"
  [cell_1spe]="--preset paper --backend cell --spes 1"
  [cell_1spe_fidelity]="--preset paper --backend cell --spes 1 --min-angle 0 --cost quadric --tolerance-relative 0.005"
  [fe_defaults]=""
  [fe_cell_1spe]="--backend cell --spes 1"
  [fe_quadric]="--cost quadric --ratio 0.05"
  [fe_threads3]="--threads 3"
  [fe_cell_4spe]="--backend cell --spes 4 --spe-threads 2"
  [fe_quadric_cell_3spe]="--cost quadric --ratio 0.05 --backend cell --spes 3"
)
# The deterministic schedule (the fe preset's) gives one output for any thread or SPE count and
# either back end: these sets must equal the one-thread native set named after them.
declare -A same_as=([fe_threads3]=fe_defaults [fe_cell_4spe]=fe_defaults
  [fe_quadric_cell_3spe]=fe_quadric)
meshes=(blade.off fandisk.off femur.off rotor_small.off fandisk_groups_fields.ply)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
actual=$work/hashes.txt
for name in $(printf '%s\n' "${!option_sets[@]}" | sort); do
  for mesh in "${meshes[@]}"; do
    out=$work/${name}_${mesh%.*}.ply
    # shellcheck disable=SC2086
    if ! "$femsimp" simplify "$data/$mesh" "$out" --threads 1 --quiet ${option_sets[$name]} \
      >"$work/log" 2>&1; then
      echo "FAILED: femsimp simplify $mesh --threads 1 ${option_sets[$name]}" >&2
      cat "$work/log" >&2
      exit 1
    fi
    echo "$name $mesh $(sha256sum "$out" | cut -d' ' -f1)" >>"$actual"
  done
done
for name in "${!same_as[@]}"; do
  for mesh in "${meshes[@]}"; do
    mine=$(awk -v n="$name" -v m="$mesh" '$1 == n && $2 == m {print $3}' "$actual")
    theirs=$(awk -v n="${same_as[$name]}" -v m="$mesh" '$1 == n && $2 == m {print $3}' "$actual")
    if [ "$mine" != "$theirs" ]; then
      echo "$name $mesh differs from ${same_as[$name]} $mesh: the schedule is not deterministic" >&2
      exit 1
    fi
  done
done
if [ "$mode" = --update ]; then
  cp "$actual" "$hashes"
  echo "recorded $(wc -l <"$actual") outputs in $hashes"
  exit 0
fi
if ! diff -u "$hashes" "$actual"; then
  echo "outputs differ from the recorded ones (lines marked + are this build's)" >&2
  exit 1
fi
echo "all $(wc -l <"$actual") outputs identical to the recorded ones"
