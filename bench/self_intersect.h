// Self-intersection check of a triangle soup with CGAL, kept in its own translation unit
// because CGAL's headers dominate the build time.
#pragma once

#include <cstdint>

#include "engine/raw_mesh.h"

namespace femsimp::bench {

// Number of intersecting face pairs is not needed: true if any two non-adjacent faces
// intersect. Non-manifold soups are split into manifold pieces first (orient_polygon_soup).
bool DoesSelfIntersect(const RawMesh& mesh);

}  // namespace femsimp::bench
