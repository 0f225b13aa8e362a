// CGAL's edge-collapse simplification bounded by its Polyhedral_envelope_filter
// (bench/fidelity_table.cc).
#pragma once

#include "bench/peers/peer_run.h"

namespace femsimp::bench {

// Configured as CGAL 5.5's own example (edge_collapse_envelope.cpp): Lindstrom-Turk cost and
// placement, Bounded_normal_change_filter inside Polyhedral_envelope_filter(tolerance), no
// count target (Count_stop_predicate 0: until the queue is empty). Stops after `time_limit`
// CPU seconds (0: none) and says so (timed_out). An input CGAL's Surface_mesh refuses (e.g. a
// non-manifold one) is an error.
PeerRun RunCgalEnvelope(const RawMesh& input, double tolerance, double time_limit);

}  // namespace femsimp::bench
