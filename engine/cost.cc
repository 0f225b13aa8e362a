#include "engine/cost.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace femsimp {

float GaussianCurvatureCost::Cost(const Ring& ring) const {
  const double cx = ring.center_pos.x, cy = ring.center_pos.y, cz = ring.center_pos.z;
  const int n = ring.neighbours();
  double sum = 0.0;
  for (int i = 0; i < ring.faces; ++i) {
    const Vec3& b = ring.pos[i];
    const Vec3& c = ring.pos[(i + 1) % n];
    const double ux = b.x - cx, uy = b.y - cy, uz = b.z - cz;
    const double wx = c.x - cx, wy = c.y - cy, wz = c.z - cz;
    const double cross = std::sqrt((uy * wz - uz * wy) * (uy * wz - uz * wy) +
                                   (uz * wx - ux * wz) * (uz * wx - ux * wz) +
                                   (ux * wy - uy * wx) * (ux * wy - uy * wx));
    sum += std::atan2(cross, ux * wx + uy * wy + uz * wz);
  }
  const double full = ring.boundary ? std::numbers::pi : 2.0 * std::numbers::pi;
  return static_cast<float>(std::fabs(full - sum));
}

float DeviationCost::Cost(const Ring& ring) const {
  float worst = 0.0f;
  for (int i = 0; i < ring.faces; ++i)
    worst = std::max(worst, face_attrs_[FaceOf(ring.out[i])].error);
  // The curvature (at most 2 pi) only breaks ties: 1e-3 of it is below a 1 % step of the bound.
  return worst / tolerance_ + 1e-3f * curvature_.Cost(ring);
}

}  // namespace femsimp
