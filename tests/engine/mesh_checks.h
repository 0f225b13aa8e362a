// Independent checks of simplification outputs, computed from the triangle soup and the raw
// half-edge arrays rather than through the engine's own walks.
#pragma once

#include <string>

#include "engine/mesh.h"
#include "engine/raw_mesh.h"

namespace femsimp::testing {

struct SurfaceTopology {
  long vertices = 0, edges = 0, faces = 0;
  long boundary_edges = 0;
  long components = 0;
  long euler() const { return vertices - edges + faces; }
};

// Counts over referenced vertices only.
SurfaceTopology Topology(const RawMesh& mesh);

// Every live face's half-edges: twins mutual and reversed, targets live; every live vertex's
// outgoing half-edge leaves it from a live face, and on a boundary has no twin; every live
// vertex is used by a face. Returns "" or a description of the first violation.
std::string HalfEdgeInvariantViolation(const Mesh& mesh);

// Smallest interior angle (degrees) of a triangle of the soup.
double MinAngleDegrees(const RawMesh& mesh, size_t face);

RawMesh LoadTestMesh(const std::string& name);  // from tests/data, fails the test if missing

}  // namespace femsimp::testing
