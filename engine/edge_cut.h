// Whether a triangle lies within a distance of two triangles across an edge, by cutting it
// between them (the measured check's pair certificate, engine/coverage.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/vec.h"

namespace femsimp {

// A plane through the edge ab of t = (a, b, c1) and u = (b, a, c2) that halves the angle between
// them: the points on t's side are mostly nearer t, the others nearer u.
class EdgeCut {
 public:
  EdgeCut() = default;
  EdgeCut(const DVec3& a, const DVec3& b, const DVec3& c1, const DVec3& c2) : a_(a) {
    const DVec3 edge = b - a;
    const double length2 = Dot(edge, edge);
    if (!(length2 > 0)) return;
    // Each triangle's direction away from the edge, in its own plane.
    const auto away = [&](const DVec3& c) {
      const DVec3 ac = c - a;
      return ac - (Dot(ac, edge) / length2) * edge;
    };
    const DVec3 to_t = away(c1), to_u = away(c2);
    const double t_length = Norm(to_t), u_length = Norm(to_u);
    if (!(t_length > 0) || !(u_length > 0)) return;
    normal_ = (1.0 / t_length) * to_t - (1.0 / u_length) * to_u;
    valid_ = std::isfinite(Dot(normal_, normal_)) && Dot(normal_, normal_) > 0;
  }
  // False for a degenerate triangle or edge: no plane between them.
  bool valid() const { return valid_; }
  // Positive on t's side, negative on u's.
  double Side(const DVec3& p) const { return Dot(normal_, p - a_); }

 private:
  DVec3 a_{0, 0, 0}, normal_{0, 0, 0};
  bool valid_ = false;
};

// The largest squared distance from a point of the triangle c to t or u, whichever is on its
// side of the cut, or more than `limit` as soon as one is farther. The cut splits the triangle
// into two convex parts, its corners on each side and the points where its edges cross; the
// distance to a triangle is convex, so each part's corners decide. The crossing points are on
// the triangle's edges up to rounding, as the subdivision's midpoints are: whatever the plane,
// the segment between them splits the triangle into those two parts, so the plane only decides
// how tight the answer is. A corner on the plane counts on both sides. corner_to_t(q) and
// corner_to_u(q) give corner q's squared distances (the caller may know them already), to_t(p)
// and to_u(p) any point's.
template <class CornerToT, class CornerToU, class ToT, class ToU>
double CutWorst(const EdgeCut& cut, const DVec3* c, CornerToT&& corner_to_t,
                CornerToU&& corner_to_u, ToT&& to_t, ToU&& to_u, double limit) {
  double side[3];
  double worst = 0;
  for (int q = 0; q < 3; ++q) {
    side[q] = cut.Side(c[q]);
    // NaN would put the corner on neither side.
    if (std::isnan(side[q])) return std::numeric_limits<double>::infinity();
    if (side[q] >= 0) worst = std::max(worst, corner_to_t(q));
    if (side[q] <= 0) worst = std::max(worst, corner_to_u(q));
    if (worst > limit) return worst;
  }
  for (int q = 0; q < 3; ++q) {
    const int r = q == 2 ? 0 : q + 1;
    if (!((side[q] > 0 && side[r] < 0) || (side[q] < 0 && side[r] > 0))) continue;
    const double along = std::clamp(side[q] / (side[q] - side[r]), 0.0, 1.0);
    const DVec3 crossing = c[q] + along * (c[r] - c[q]);
    worst = std::max({worst, to_t(crossing), to_u(crossing)});
    if (worst > limit) return worst;
  }
  return worst;
}

}  // namespace femsimp
