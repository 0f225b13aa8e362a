// Checks that a simplified mesh is a valid output for its input, independent of the engine's
// own bookkeeping: femsimp-load --verify runs it on every result it receives.
#pragma once

#include <cstdint>
#include <string>

#include "absl/status/status.h"
#include "engine/raw_mesh.h"

namespace femsimp::cli {

// Topology of a triangle soup, counted over the vertices that faces use.
struct SoupTopology {
  int64_t vertices = 0, edges = 0, faces = 0;
  int64_t boundary_edges = 0;
  int64_t components = 0;  // edge-connected groups of faces
  int64_t euler() const { return vertices - edges + faces; }
};

SoupTopology TopologyOf(const RawMesh& mesh);

// The output passes the engine's input validation (finite, manifold, consistently oriented,
// no degenerate or duplicate face), is not larger than the input, and keeps its topology: same
// Euler characteristic and components, closed stays closed. Messages say what differs.
absl::Status CheckOutput(const SoupTopology& input, const RawMesh& output);

}  // namespace femsimp::cli
