#include "engine/transversal_crossing.h"

#include <cmath>

namespace femsimp {
namespace {

// The sign of the orientation of d against the plane through a, b and c, when floating point
// decides it: +1 or -1, or 0 where the computed value is within its error bound of zero.
// The bound is Shewchuk's for this evaluation order ("Adaptive precision floating-point
// arithmetic and fast robust geometric predicates", 1997: (7 + 56 eps) eps times the
// permanent), which covers the rounding of the differences too.
struct Side {
  int sign;
  double value;
};

Side Orientation(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d) {
  constexpr double kEps = 0x1p-53;
  constexpr double kBound = (7.0 + 56.0 * kEps) * kEps;
  const DVec3 ad = a - d, bd = b - d, cd = c - d;
  const double bxcy = bd.x * cd.y, cxby = cd.x * bd.y;
  const double cxay = cd.x * ad.y, axcy = ad.x * cd.y;
  const double axby = ad.x * bd.y, bxay = bd.x * ad.y;
  const double det = ad.z * (bxcy - cxby) + bd.z * (cxay - axcy) + cd.z * (axby - bxay);
  const double permanent = (std::fabs(bxcy) + std::fabs(cxby)) * std::fabs(ad.z) +
                           (std::fabs(cxay) + std::fabs(axcy)) * std::fabs(bd.z) +
                           (std::fabs(axby) + std::fabs(bxay)) * std::fabs(cd.z);
  // Below this the products may have lost bits to underflow, which the bound does not cover.
  constexpr double kSmallest = 0x1p-900;
  if (!(permanent > kSmallest)) return {0, det};
  const double bound = kBound * permanent;
  return {det > bound ? 1 : det < -bound ? -1 : 0, det};
}

// The segment pq through the inside of abc, when p and q lie certainly on opposite sides of its
// plane (sp, sq) and the line pq certainly passes inside each of its edges.
std::optional<DVec3> Pierce(const DVec3& p, const DVec3& q, const Side& sp, const Side& sq,
                            const Triangle& t) {
  if (sp.sign == 0 || sq.sign != -sp.sign) return std::nullopt;
  const int s0 = Orientation(p, q, t.p[0], t.p[1]).sign;
  if (s0 == 0) return std::nullopt;
  if (Orientation(p, q, t.p[1], t.p[2]).sign != s0) return std::nullopt;
  if (Orientation(p, q, t.p[2], t.p[0]).sign != s0) return std::nullopt;
  return p + (sp.value / (sp.value - sq.value)) * (q - p);
}

// Each edge of `edges` against the face `face`, given the sides of its corners.
std::optional<DVec3> EdgeThrough(const Triangle& edges, const Side (&side)[3],
                                 const Triangle& face) {
  for (int k = 0; k < 3; ++k) {
    const int n = (k + 1) % 3;
    if (auto at = Pierce(edges.p[k], edges.p[n], side[k], side[n], face)) return at;
  }
  return std::nullopt;
}

bool AllOnOneSide(const Side (&side)[3]) {
  return side[0].sign != 0 && side[1].sign == side[0].sign && side[2].sign == side[0].sign;
}

}  // namespace

std::optional<DVec3> TransversalCrossing(const Triangle& a, const Triangle& b) {
  Side a_of_b[3], b_of_a[3];  // a's corners against b's plane, b's against a's
  for (int k = 0; k < 3; ++k) a_of_b[k] = Orientation(b.p[0], b.p[1], b.p[2], a.p[k]);
  if (AllOnOneSide(a_of_b)) return std::nullopt;
  for (int k = 0; k < 3; ++k) b_of_a[k] = Orientation(a.p[0], a.p[1], a.p[2], b.p[k]);
  if (AllOnOneSide(b_of_a)) return std::nullopt;
  if (auto at = EdgeThrough(a, a_of_b, b)) return at;
  return EdgeThrough(b, b_of_a, a);
}

}  // namespace femsimp
