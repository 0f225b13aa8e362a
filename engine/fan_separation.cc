#include "engine/fan_separation.h"

#include <algorithm>
#include <cmath>

namespace femsimp {
namespace {

constexpr double kSeparationMargin = 1e-8;

double Cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// c = Cross2(a, b) is clearly positive: beyond kSeparationMargin of |a| |b|.
bool ClearlyLeft(double c, double aa, double bb) {
  return c > 0 && c * c > kSeparationMargin * kSeparationMargin * aa * bb;
}

double MaxAbs(const DVec3& q) { return std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)}); }

}  // namespace

bool FanSeparation::Prepare(const Ring& fan, const uint32_t* ids) {
  if (fan.boundary || fan.faces < 3) return false;
  const int k = corners_ = fan.faces;
  origin_ = ToD(fan.center_pos);
  DVec3 q[kMaxRing];
  DVec3 n{0, 0, 0};
  for (int i = 0; i < k; ++i) q[i] = ToD(fan.pos[i]) - origin_;
  for (int i = 0; i < k; ++i) n = n + Cross(q[i], q[(i + 1) % k]);
  const double length = Norm(n);
  if (!(length > 0)) return false;
  n_ = {n.x / length, n.y / length, n.z / length};
  // The axis least along n, made square to it.
  const DVec3 axis = std::fabs(n_.x) <= std::fabs(n_.y) && std::fabs(n_.x) <= std::fabs(n_.z)
                         ? DVec3{1, 0, 0}
                         : (std::fabs(n_.y) <= std::fabs(n_.z) ? DVec3{0, 1, 0} : DVec3{0, 0, 1});
  const double along = Dot(axis, n_);
  e1_ = axis - DVec3{along * n_.x, along * n_.y, along * n_.z};
  const double e1_length = Norm(e1_);
  e1_ = {e1_.x / e1_length, e1_.y / e1_length, e1_.z / e1_length};
  e2_ = Cross(n_, e1_);
  low_ = high_ = Dot(q[0], n_);
  extent_ = 0;
  for (int i = 0; i < k; ++i) {
    ring_[i] = Project(q[i]);
    id_[i] = ids[i];
    const double h = Dot(q[i], n_);
    low_ = std::min(low_, h);
    high_ = std::max(high_, h);
    extent_ = std::max(extent_, MaxAbs(q[i]));
  }
  // Every triangle (V, nbr[i], nbr[i + 1]) is clearly counter-clockwise and the ring crosses
  // the ray from V along e1 once: it winds once around V (its angle around V grows by less than
  // half a turn a step), a simple polygon star-shaped around V.
  int crossings = 0, lowest = 0;
  for (int i = 0; i < k; ++i) {
    const Flat& b = ring_[i];
    const Flat& c = ring_[(i + 1) % k];
    if (!ClearlyLeft(Cross2(b.x, b.y, c.x, c.y), b.x * b.x + b.y * b.y, c.x * c.x + c.y * c.y))
      return false;
    crossings += b.y < 0 && c.y >= 0;
    if (b.y < ring_[lowest].y || (b.y == ring_[lowest].y && b.x < ring_[lowest].x)) lowest = i;
  }
  if (crossings != 1) return false;
  // Its convex hull: a Graham scan in the ring's order (by angle around V, inside the hull) from
  // its lowest corner (on the hull). A corner that does not turn left is dropped.
  const auto turn = [this](int a, int b, int c) {
    return Cross2(ring_[b].x - ring_[a].x, ring_[b].y - ring_[a].y, ring_[c].x - ring_[b].x,
                  ring_[c].y - ring_[b].y);
  };
  hull_size_ = 0;
  for (int m = 0; m <= k; ++m) {
    const int i = (lowest + m) % k;
    while (hull_size_ >= 2 && turn(hull_[hull_size_ - 2], hull_[hull_size_ - 1], i) <= 0)
      --hull_size_;
    if (m < k) hull_[hull_size_++] = i;
  }
  if (hull_size_ < 3) return false;
  // Every hull corner turns left clearly; the sides and corner angles below are the hull's.
  for (int i = 0; i < k; ++i) hull_at_[i] = -1;
  for (int m = 0; m < hull_size_; ++m) {
    const int a = hull_[(m + hull_size_ - 1) % hull_size_], b = hull_[m];
    const int c = hull_[(m + 1) % hull_size_];
    const Flat u{ring_[b].x - ring_[a].x, ring_[b].y - ring_[a].y};
    const Flat w{ring_[c].x - ring_[b].x, ring_[c].y - ring_[b].y};
    if (!ClearlyLeft(turn(a, b, c), u.x * u.x + u.y * u.y, w.x * w.x + w.y * w.y)) return false;
    hull_at_[b] = m;
  }
  // And holds the corners it left out (dents: rare), none clearly beyond a side.
  for (int i = 0; i < k; ++i) {
    if (hull_at_[i] >= 0) continue;
    for (int m = 0; m < hull_size_; ++m) {
      const int a = hull_[m], b = hull_[(m + 1) % hull_size_];
      const Flat u{ring_[b].x - ring_[a].x, ring_[b].y - ring_[a].y};
      const Flat w{ring_[i].x - ring_[a].x, ring_[i].y - ring_[a].y};
      if (ClearlyLeft(-Cross2(u.x, u.y, w.x, w.y), u.x * u.x + u.y * u.y, w.x * w.x + w.y * w.y))
        return false;
    }
  }
  return true;
}

bool FanSeparation::Covers(int target) const {
  const int k = corners_;
  const Flat& d = ring_[target];
  for (int i = 0; i < k; ++i) {
    const int j = (i + 1) % k;
    if (i == target || j == target) continue;
    const double ux = ring_[i].x - d.x, uy = ring_[i].y - d.y;
    const double wx = ring_[j].x - d.x, wy = ring_[j].y - d.y;
    if (!ClearlyLeft(Cross2(ux, uy, wx, wy), ux * ux + uy * uy, wx * wx + wy * wy)) return false;
  }
  return true;
}

// F's corners other than ring corner r, a and b: the hull's angle at r and F's angle there (both
// convex) meet only at r, clearly: each side of either lies clearly outside the other.
bool FanSeparation::ConeApart(int r, const Flat& a, const Flat& b, int* tests) const {
  const Flat& o = ring_[r];
  // The hull's angle at r runs counter-clockwise from its side to the next hull corner to its
  // side to the one before.
  const int m = hull_at_[r];
  const Flat& next = ring_[hull_[(m + 1) % hull_size_]];
  const Flat& before = ring_[hull_[(m + hull_size_ - 1) % hull_size_]];
  const Flat u1{next.x - o.x, next.y - o.y};
  const Flat u2{before.x - o.x, before.y - o.y};
  Flat w1{a.x - o.x, a.y - o.y}, w2{b.x - o.x, b.y - o.y};
  const auto length2 = [](const Flat& v) { return v.x * v.x + v.y * v.y; };
  const auto cross = [](const Flat& v, const Flat& w) { return Cross2(v.x, v.y, w.x, w.y); };
  *tests += 1;
  const double turn = cross(w1, w2);
  if (!ClearlyLeft(std::fabs(turn), length2(w1), length2(w2))) return false;
  if (turn < 0) std::swap(w1, w2);
  // Side d lies clearly outside the angle from s to e (counter-clockwise, below half a turn):
  // clearly clockwise of s, or clearly counter-clockwise of e.
  const auto outside = [&](const Flat& d, const Flat& s, const Flat& e) {
    *tests += 2;
    return ClearlyLeft(-cross(s, d), length2(s), length2(d)) ||
           ClearlyLeft(-cross(d, e), length2(d), length2(e));
  };
  return outside(w1, u1, u2) && outside(w2, u1, u2) && outside(u1, w1, w2) && outside(u2, w1, w2);
}

// All of f strictly right of one side of the hull.
bool FanSeparation::BeyondASide(const Flat f[3], int* tests) const {
  for (int m = 0; m < hull_size_; ++m) {
    const Flat& a = ring_[hull_[m]];
    const Flat& b = ring_[hull_[(m + 1) % hull_size_]];
    const double ux = b.x - a.x, uy = b.y - a.y, uu = ux * ux + uy * uy;
    bool beyond = true;
    for (int c = 0; c < 3 && beyond; ++c) {
      ++*tests;
      const double wx = f[c].x - a.x, wy = f[c].y - a.y;
      beyond = ClearlyLeft(-Cross2(ux, uy, wx, wy), uu, wx * wx + wy * wy);
    }
    if (beyond) return true;
  }
  return false;
}

bool FanSeparation::Apart(const Triangle& face, int* tests) const {
  const int k = corners_;
  int at[3];  // the ring corner each corner of the face is, or -1
  int shared = 0;
  for (int c = 0; c < 3; ++c) {
    at[c] = -1;
    for (int i = 0; i < k; ++i)
      if (face.id[c] == id_[i]) {
        at[c] = i;
        ++shared;
        break;
      }
  }
  Flat f[3];
  double h[3], reach = extent_;
  for (int c = 0; c < 3; ++c) {
    const DVec3 q = face.p[c] - origin_;
    f[c] = Project(q);
    h[c] = Dot(q, n_);
    reach = std::max(reach, MaxAbs(q));
  }
  if (shared == 0) {
    *tests += 1;
    const double margin = 4 * kSeparationMargin * reach;
    if ((h[0] > high_ + margin && h[1] > high_ + margin && h[2] > high_ + margin) ||
        (h[0] < low_ - margin && h[1] < low_ - margin && h[2] < low_ - margin))
      return true;
    return BeyondASide(f, tests);
  }
  if (shared == 1) {
    const int c = at[0] >= 0 ? 0 : (at[1] >= 0 ? 1 : 2);
    if (hull_at_[at[c]] < 0) return false;  // a corner inside the hull
    return ConeApart(at[c], f[(c + 1) % 3], f[(c + 2) % 3], tests);
  }
  if (shared == 2) {
    const int c = at[0] < 0 ? 0 : (at[1] < 0 ? 1 : 2);  // the corner off the ring
    int i = at[(c + 1) % 3], j = at[(c + 2) % 3];
    if ((j + 1) % k == i) std::swap(i, j);
    // A side of the ring that is a side of the hull.
    if ((i + 1) % k != j || hull_at_[i] < 0 || hull_[(hull_at_[i] + 1) % hull_size_] != j)
      return false;
    const Flat& a = ring_[i];
    const Flat& b = ring_[j];
    const double ux = b.x - a.x, uy = b.y - a.y, wx = f[c].x - a.x, wy = f[c].y - a.y;
    *tests += 1;
    return ClearlyLeft(-Cross2(ux, uy, wx, wy), ux * ux + uy * uy, wx * wx + wy * wy);
  }
  return false;
}

}  // namespace femsimp
