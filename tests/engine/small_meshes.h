// Tiny hand-made meshes for exercising single collapses.
#pragma once

#include "engine/raw_mesh.h"

namespace femsimp::testing {

RawMesh FlatGrid(int n);  // (n+1)^2 vertices on the unit square, open boundary
RawMesh Tetrahedron();
RawMesh Octahedron();
RawMesh SingleTriangle();

}  // namespace femsimp::testing
