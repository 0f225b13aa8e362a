// Two faces lying in one plane whose insides overlap: what bodies exported apart leave where they
// touch (a block standing on a plate, its bottom facets on the plate's top facets, the two
// triangulated independently). Such a contact is no crossing (engine/transversal_crossing.h
// leaves it out), yet tetgen and most FE meshers refuse overlapping facets, so a report needs
// it found and measured.
#pragma once

#include <optional>

#include "engine/triangle_intersection.h"

namespace femsimp {

struct PlanarOverlap {
  double area = 0.0;  // of the common part of the two faces
  DVec3 at{};         // its centroid
};

// The common part of a and b when each has its corners within plane_tolerance of the other's
// plane and that part has an area above a millionth of the smaller face's (a shared edge or
// corner, or rounding along one, is no overlap); none otherwise, and for zero-area faces.
std::optional<PlanarOverlap> OverlapInPlane(const Triangle& a, const Triangle& b,
                                            double plane_tolerance);

}  // namespace femsimp
