// meshoptimizer's meshopt_simplify bounded by its target_error (bench/fidelity_table.cc).
#pragma once

#include "bench/peers/peer_run.h"

namespace femsimp::bench {

// Simplifies until meshoptimizer's own error estimate would exceed `tolerance` (model units),
// with no target count (target index count 0: as far as the error allows) and no options.
PeerRun RunMeshoptError(const RawMesh& input, double tolerance);

}  // namespace femsimp::bench
