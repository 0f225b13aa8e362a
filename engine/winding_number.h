// The winding number of a closed triangle surface about a point: the solid angle its facets
// subtend there over 4π (Van Oosterom and Strackee's formula per facet). About 1 inside a
// surface that faces outward, -1 inside one that faces inward, 0 outside; it says which closed
// shells of a part lie inside which (a cavity) without a ray that may graze an edge.
#pragma once

#include <cmath>
#include <numbers>

#include "engine/vec.h"

namespace femsimp {

// Facet (a, b, c)'s share of the winding number about p.
inline double WindingShare(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3 u = a - p, v = b - p, w = c - p;
  const double lu = Norm(u), lv = Norm(v), lw = Norm(w);
  const double numerator = Dot(u, Cross(v, w));
  const double denominator = lu * lv * lw + Dot(u, v) * lw + Dot(u, w) * lv + Dot(v, w) * lu;
  return std::atan2(numerator, denominator) / (2 * std::numbers::pi);
}

}  // namespace femsimp
