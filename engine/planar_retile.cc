#include "engine/planar_retile.h"

#include <cmath>

namespace femsimp {
namespace {

struct P2 {
  double u, v;
};

// The sign of the 2D orientation of (a, b, c) when certain in double arithmetic (Shewchuk's
// ccwerrboundA: it covers the rounding of the differences and of the products), else 0.
int CertainOrientation(const P2& a, const P2& b, const P2& c) {
  constexpr double kEps = 0x1p-53;
  constexpr double kBound = (3.0 + 16.0 * kEps) * kEps;
  const double left = (b.u - a.u) * (c.v - a.v);
  const double right = (b.v - a.v) * (c.u - a.u);
  const double det = left - right;
  if (std::fabs(det) > kBound * (std::fabs(left) + std::fabs(right))) return det > 0 ? 1 : -1;
  return 0;
}

// The axis whose coordinate V and every ring point share exactly, or -1.
int SharedAxis(const Ring& fan, int* tests) {
  const float c[3] = {fan.center_pos.x, fan.center_pos.y, fan.center_pos.z};
  for (int a = 0; a < 3; ++a) {
    bool shared = true;
    for (int i = 0; i < fan.faces && shared; ++i) {
      const float p[3] = {fan.pos[i].x, fan.pos[i].y, fan.pos[i].z};
      shared = p[a] == c[a];
      ++*tests;
    }
    if (shared) return a;
  }
  return -1;
}

}  // namespace

bool RetilesTheFanInItsPlane(const Ring& fan, int target, int* tests) {
  int ignored = 0;
  if (tests == nullptr) tests = &ignored;
  const int n = fan.faces;
  if (fan.boundary || n < 3 || target < 0 || target >= n) return false;
  const int axis = SharedAxis(fan, tests);
  if (axis < 0) return false;
  const auto flat = [axis](const Vec3& p) {
    const double q[3] = {p.x, p.y, p.z};
    return P2{q[(axis + 1) % 3], q[(axis + 2) % 3]};
  };
  const P2 c = flat(fan.center_pos);
  P2 ring[kMaxRing];
  for (int i = 0; i < n; ++i) ring[i] = flat(fan.pos[i]);
  const int sign = CertainOrientation(c, ring[0], ring[1]);
  if (sign == 0) return false;
  // Every old triangle of one orientation, and the ring around V once: the ring's edges that
  // cross the line v = c.v on V's side u > c.u all cross it one way (that orientation), so
  // their count is the winding number. Half-open on v, so that a ring point on the line counts
  // once.
  int crossings = 0;
  for (int i = 0; i < n; ++i) {
    const P2& p = ring[i];
    const P2& q = ring[(i + 1) % n];
    ++*tests;
    if (CertainOrientation(c, p, q) != sign) return false;
    crossings += sign > 0 ? (p.v <= c.v && q.v > c.v) : (p.v > c.v && q.v <= c.v);
  }
  if (crossings != 1) return false;
  // The new triangles: every fan face but the two that contain Vd, with Vd for V.
  const P2& d = ring[target];
  for (int f = 0; f < n; ++f) {
    const int g = (f + 1) % n;
    if (f == target || g == target) continue;
    ++*tests;
    if (CertainOrientation(d, ring[f], ring[g]) != sign) return false;
  }
  return true;
}

}  // namespace femsimp
