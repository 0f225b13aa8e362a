// Filling an opening that lies in one plane (a flat CAD face an exporter dropped): the region its
// loops bound in that plane, triangulated without adding a point.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"

namespace femsimp {

// Newell's normal of a closed polygon: twice its area long, pointing the way its winding turns
// (right hand); well defined for a polygon that is not quite plane.
std::array<double, 3> NewellNormal(const std::array<double, 3>* corners, size_t n);

// The triangles that fill the region bounded by `loops` (closed polygons whose corners lie in one
// plane, `normal` across it): a point is inside when an odd number of loops wind around it, so a
// face with holes is one outer loop and one loop per hole. The triangulation is the region's
// constrained Delaunay triangulation in its plane (the one whose smallest angle is largest among
// those on these corners), each triangle's corners indexed into the loops' corners counted in
// order (loop 0's first, ...), wound counter-clockwise seen from where `normal` points.
// InvalidArgument where the loops do not bound such a region: an edge crossing or touching another
// (or a corner on it), two corners at one point, a loop of fewer than three corners or of no area.
absl::StatusOr<std::vector<std::array<uint32_t, 3>>> FillPlaneRegion(
    const std::vector<std::vector<std::array<double, 3>>>& loops,
    const std::array<double, 3>& normal);

}  // namespace femsimp
