// What the kernel needs to keep a run's fidelity promises (docs/FIDELITY.md): the feature
// rules, the tolerance on the tracked deviation bound, the face fields and the global budgets.
#pragma once

#include "engine/mechanics.h"

namespace femsimp {

struct FidelityConfig {
  double cos_feature = 0.0;  // a feature line turning more than this at a vertex is a corner
  float tolerance = 0.0f;    // > 0: track the deviation bound and keep it below this
  int fields = 0;            // face fields carried (their values travel in FaceAttrQ)
  bool quadric = false;      // quadric cost: accumulate quadrics, rank directions by them
  bool closed = false;       // mass properties of the solid rather than of the surface
  const GroupIndex* groups = nullptr;  // dense group slots, when fields are carried
  MechanicsLedger* ledger = nullptr;   // when mass budgets or fields are on

  bool tracks_error() const { return tolerance > 0.0f; }
  bool reads_attrs() const { return tracks_error() || fields > 0; }
};

}  // namespace femsimp
