// A facet turned over onto its neighbour within their plane: a fold. Two facets (a, b, c) and
// (b, a, d), oriented alike, that lie in one plane yet face opposite ways cover the region near
// their edge twice, once each way. Such a pair crosses nothing (engine/crossings.h leaves facets
// with a common edge out) and Mesh::Build accepts it, but tetgen and FE meshers refuse it (the
// two facets intersect in their plane). CAD tessellators leave them where a vertex sits inside
// its neighbour's triangle and the wrong diagonal of the quad was taken; flipping the edge to
// the other diagonal, (a, d, c) and (b, c, d), covers the same region once, without moving a
// point.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>

#include "engine/vec.h"

namespace femsimp {

// Each apex within this fraction of its distance from the edge line off the other facet's
// plane: an opening angle under about 0.06 degrees, far below any edge a part is made with.
inline constexpr double kFoldSine = 1e-3;

// For facets s and t (three vertex ids each) with exactly an edge in common that they run
// opposite ways (oriented alike): the corner of s off that edge, i, and t's, j, so that s is
// (a, b, c) = (s[i + 1], s[i + 2], s[i]) and t is (b, a, d) with d = t[j] (indices mod 3).
// None for facets with another number of corners in common, or that run the edge the same way
// (misoriented: they face no way, so never fold).
std::optional<std::pair<int, int>> OppositeApexes(const uint32_t* s, const uint32_t* t);

// Whether (a, b, c) and (b, a, d) fold onto each other: they face opposite ways, and each apex
// lies within plane_tolerance (the coordinates' rounding), or within kFoldSine of its distance
// from the edge line, of the other facet's plane. Zero-area facets never fold.
bool IsFold(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d, double plane_tolerance);

// Whether replacing the pair with (a, d, c) and (b, c, d) unfolds it: both new facets face the
// way the pair does on balance (the sum of their area vectors, which the flip keeps), and
// neither is a sliver (its area at least 1e-6 of the pair's net area). A pair whose facets
// cancel out (a double-sided sheet) has no way to face and is never flipped.
bool FlipUnfolds(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d);

}  // namespace femsimp
