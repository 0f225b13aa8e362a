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

// The corner of x whose vertex y lacks (the first, or 3: none).
int CornerOff(const uint32_t* x, const uint32_t* y) {
  for (int i = 0; i < 3; ++i)
    if (x[i] != y[0] && x[i] != y[1] && x[i] != y[2]) return i;
  return 3;
}

}  // namespace

std::optional<std::pair<int, int>> OppositeApexes(const uint32_t* s, const uint32_t* t) {
  const int i = CornerOff(s, t), j = CornerOff(t, s);
  if (i == 3 || j == 3) return std::nullopt;
  const uint32_t a = s[(i + 1) % 3], b = s[(i + 2) % 3];
  if (t[(j + 1) % 3] != b || t[(j + 2) % 3] != a) return std::nullopt;
  return std::pair(i, j);
}

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
