// Point-to-triangle distances, the measured check's measure (engine/coverage.h): exact up to
// rounding, and never below the true distance by more than a few ulps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "engine/vec.h"

namespace femsimp {

// The squared distance from q to the triangle (a, b, c); degenerate triangles included.
double SquaredDistanceToTriangle(const DVec3& q, const DVec3& a, const DVec3& b, const DVec3& c);
// Squared distance from q to the segment ab (a point when a = b).
double SquaredDistanceToSegment(const DVec3& q, const DVec3& a, const DVec3& b);

// Squared distances from many points to one triangle: a point over the triangle's inside is
// its height over the plane (the usual case for the pieces a new face takes), the others go
// to SquaredDistanceToTriangle. Thin triangles always do (their inside test would round).
class TriangleDistance {
 public:
  TriangleDistance() = default;
  explicit TriangleDistance(const DVec3* t)
      : t_{t[0], t[1], t[2]}, ab_(t[1] - t[0]), ac_(t[2] - t[0]) {
    const double bb = Dot(ab_, ab_), bc = Dot(ab_, ac_), cc = Dot(ac_, ac_);
    const double det = bb * cc - bc * bc;
    const DVec3 normal = Cross(ab_, ac_);
    const double length = Norm(normal);
    if (!(det > 1e-6 * bb * cc) || !(length > 0)) return;
    s_ = {cc / det, -bc / det};
    u_ = {-bc / det, bb / det};
    n_ = (1.0 / length) * normal;
    bc_ = ac_ - ab_;
    ab_ab_ = bb;
    ab_ac_ = bc;
    inverse_ab2_ = 1.0 / bb;
    inverse_ac2_ = 1.0 / cc;
    inverse_bc2_ = 1.0 / Dot(bc_, bc_);
    over_ = true;
  }
  double operator()(const DVec3& q) const {
    if (over_) {
      const DVec3 d = q - t_[0];
      const double p = Dot(d, ab_), r = Dot(d, ac_);
      const double s = s_[0] * p + s_[1] * r, u = u_[0] * p + u_[1] * r;
      if (s >= 0 && u >= 0 && s + u <= 1) {
        const double h = Dot(d, n_);
        return h * h;
      }
      // Outside the prism, the nearest point is on an edge whose line has q's projection on its
      // far side (one or two of them). Each is a point of the triangle, so rounding keeps the
      // distance from falling below the true one by more than a few ulps; the dot products
      // along ab and ac are the ones above.
      const auto along = [](const DVec3& from, const DVec3& edge, double t) {
        const DVec3 gap = from - std::clamp(t, 0.0, 1.0) * edge;
        return Dot(gap, gap);
      };
      double nearest = std::numeric_limits<double>::infinity();
      if (u < 0) nearest = along(d, ab_, p * inverse_ab2_);
      if (s < 0) nearest = std::min(nearest, along(d, ac_, r * inverse_ac2_));
      if (s + u > 1) {
        // Dot(q - b, c - b) from the same two products.
        const double t = ((r - ab_ac_) - (p - ab_ab_)) * inverse_bc2_;
        nearest = std::min(nearest, along(d - ab_, bc_, t));
      }
      return nearest;
    }
    return SquaredDistanceToTriangle(q, t_[0], t_[1], t_[2]);
  }
  // The largest of the three corners', or more than `limit` as soon as one is farther.
  double Corners(const DVec3 corners[3], double limit) const {
    double worst = 0;
    for (int i = 0; i < 3; ++i) {
      worst = std::max(worst, (*this)(corners[i]));
      if (worst > limit) break;
    }
    return worst;
  }

 private:
  DVec3 t_[3]{};
  DVec3 ab_{0, 0, 0}, ac_{0, 0, 0}, n_{0, 0, 0}, bc_{0, 0, 0};
  std::array<double, 2> s_{}, u_{};  // rows of the inverse Gram matrix of ab, ac
  double ab_ab_ = 0, ab_ac_ = 0;     // ab.ab, ab.ac
  double inverse_ab2_ = 0, inverse_ac2_ = 0, inverse_bc2_ = 0;  // 1 / squared edge lengths
  bool over_ = false;
};

}  // namespace femsimp
