#include "engine/fold.h"

#include <algorithm>

namespace femsimp {
namespace {

// Distance of p from the line through a and b (a != b).
double DistanceFromLine(const DVec3& p, const DVec3& a, const DVec3& b) {
  return Norm(Cross(b - a, p - a)) / Norm(b - a);
}

// Whether p lies within the tolerances of the plane through `at` with normal n (|n| > 0),
// h being p's distance from the facets' common edge.
bool NearPlane(const DVec3& p, const DVec3& at, const DVec3& n, double h, double plane_tolerance) {
  const double off = std::abs(Dot(p - at, n)) / Norm(n);
  return off <= std::max(plane_tolerance, kFoldSine * h);
}

}  // namespace

bool IsFold(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d,
            double plane_tolerance) {
  const DVec3 n1 = Cross(b - a, c - a), n2 = Cross(a - b, d - b);
  if (Dot(n1, n1) == 0.0 || Dot(n2, n2) == 0.0 || Dot(n1, n2) >= 0.0) return false;
  return NearPlane(d, a, n1, DistanceFromLine(d, a, b), plane_tolerance) &&
         NearPlane(c, a, n2, DistanceFromLine(c, a, b), plane_tolerance);
}

bool FlipUnfolds(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d) {
  const DVec3 n1 = Cross(b - a, c - a), n2 = Cross(a - b, d - b), net = n1 + n2;
  const double net_area = Norm(net);
  if (net_area <= 1e-6 * (Norm(n1) + Norm(n2))) return false;
  const DVec3 m1 = Cross(d - a, c - a), m2 = Cross(c - b, d - b);
  const double floor = 1e-6 * net_area;
  return Dot(m1, net) > floor * net_area && Dot(m2, net) > floor * net_area;
}

}  // namespace femsimp
