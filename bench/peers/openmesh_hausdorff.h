// OpenMesh's Decimater bounded by its Hausdorff module (bench/fidelity_table.cc).
#pragma once

#include "bench/peers/peer_run.h"

namespace femsimp::bench {

// Quadric priorities, collapses bounded by ModHausdorff at `tolerance` (model units; it bounds
// the distance of the removed vertices to the new faces) and by ModNormalFlipping, decimate()
// until no module allows another collapse.
PeerRun RunOpenMeshHausdorff(const RawMesh& input, double tolerance);

}  // namespace femsimp::bench
