// The prepared triangle tests (engine/triangle_intersection.h) against the plain ones they
// replaced, kept here verbatim as the reference: the self-intersection rule's verdicts, and so
// the engine's outputs, must not change by a single collapse. Random pairs with shared corners,
// coplanar and nearly coplanar placements, collinear and touching cases, on a coarse lattice
// so that exact zeros and ties come often. One difference is by design and never shows here:
// a triangle strictly on one side of the other's plane is apart where the plain tests may call
// a near-touch along a sliver (tests/engine/self_intersection_test.cc has such a pair). Coplanar
// pairs that a line in their plane separates by far more than the near-touch margin are decided
// in the plane; the plain tests answer "apart" there too, and these pairs check it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "engine/triangle_intersection.h"

namespace femsimp {
namespace reference {

// engine/triangle_intersection.h and .cc before the prepared tests.
struct TriangleBox {
  DVec3 lo, hi;
  explicit TriangleBox(const Triangle& t);
  bool Overlaps(const TriangleBox& o) const {
    return !(lo.x > o.hi.x || o.lo.x > hi.x || lo.y > o.hi.y || o.lo.y > hi.y || lo.z > o.hi.z ||
             o.lo.z > hi.z);
  }
};
bool TrianglesIntersect(const Triangle& a, const Triangle& b);
bool OverlappingTrianglesIntersect(const Triangle& a, const Triangle& b);
bool SegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                          const DVec3& c);

namespace {

// Relative size below which an orientation counts as zero (coplanar or collinear): far above
// double rounding of float inputs, far below any real feature of a mesh.
constexpr double kRelativeZero = 1e-12;

// Sign of `value`, 0 when value^2 <= kRelativeZero^2 * scale2 (scale2: the squared product of
// the lengths involved, so no square root is taken).
int Sign(double value, double scale2) {
  if (value * value <= kRelativeZero * kRelativeZero * scale2) return 0;
  return value > 0 ? 1 : -1;
}

// Sign of the volume of (a, b, c, d).
int Orient3d(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d) {
  const DVec3 u = b - a, v = c - a, w = d - a;
  return Sign(Dot(Cross(u, v), w), Dot(u, u) * Dot(v, v) * Dot(w, w));
}

struct P2 {
  double x, y;
};

int Orient2d(const P2& a, const P2& b, const P2& c) {
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
  return Sign(ux * vy - uy * vx, (ux * ux + uy * uy) * (vx * vx + vy * vy));
}

// Drops the coordinate along which the plane with normal n is steepest.
struct Projection {
  int drop;
  explicit Projection(const DVec3& n) {
    const double x = std::fabs(n.x), y = std::fabs(n.y), z = std::fabs(n.z);
    drop = x >= y && x >= z ? 0 : (y >= z ? 1 : 2);
  }
  P2 operator()(const DVec3& p) const {
    if (drop == 0) return {p.y, p.z};
    if (drop == 1) return {p.z, p.x};
    return {p.x, p.y};
  }
};

bool OnSegment(const P2& p, const P2& a, const P2& b) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

// Closed 2D segments.
bool SegmentsMeet(const P2& p, const P2& q, const P2& a, const P2& b) {
  const int o1 = Orient2d(p, q, a), o2 = Orient2d(p, q, b);
  const int o3 = Orient2d(a, b, p), o4 = Orient2d(a, b, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && OnSegment(a, p, q)) || (o2 == 0 && OnSegment(b, p, q)) ||
         (o3 == 0 && OnSegment(p, a, b)) || (o4 == 0 && OnSegment(q, a, b));
}

// Closed 2D triangle (either orientation).
bool InTriangle(const P2& p, const P2& a, const P2& b, const P2& c) {
  const int s1 = Orient2d(a, b, p), s2 = Orient2d(b, c, p), s3 = Orient2d(c, a, p);
  const bool negative = s1 < 0 || s2 < 0 || s3<0, positive = s1> 0 || s2 > 0 || s3 > 0;
  return !(negative && positive);
}

bool CoplanarSegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                                  const DVec3& c) {
  const Projection flat(Cross(b - a, c - a));
  const P2 p2 = flat(p), q2 = flat(q), a2 = flat(a), b2 = flat(b), c2 = flat(c);
  return InTriangle(p2, a2, b2, c2) || InTriangle(q2, a2, b2, c2) || SegmentsMeet(p2, q2, a2, b2) ||
         SegmentsMeet(p2, q2, b2, c2) || SegmentsMeet(p2, q2, c2, a2);
}

bool MeetsTriangle(const DVec3& p, const DVec3& q, const Triangle& t) {
  return reference::SegmentMeetsTriangle(p, q, t.p[0], t.p[1], t.p[2]);
}

}  // namespace

bool SegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                          const DVec3& c) {
  for (double DVec3::*k : {&DVec3::x, &DVec3::y, &DVec3::z}) {
    const double lo = std::min({a.*k, b.*k, c.*k}), hi = std::max({a.*k, b.*k, c.*k});
    const double slack = 1e-9 * (std::fabs(lo) + std::fabs(hi));
    if (std::max(p.*k, q.*k) < lo - slack || std::min(p.*k, q.*k) > hi + slack) return false;
  }
  const int sp = Orient3d(a, b, c, p), sq = Orient3d(a, b, c, q);
  if (sp == sq && sp != 0) return false;
  if (sp == 0 && sq == 0) return CoplanarSegmentMeetsTriangle(p, q, a, b, c);
  // The line pq crosses the plane inside the segment: inside the triangle iff pq passes on the
  // same side of all three edges (or along one).
  const int s1 = Orient3d(p, q, a, b), s2 = Orient3d(p, q, b, c), s3 = Orient3d(p, q, c, a);
  const bool negative = s1 < 0 || s2 < 0 || s3<0, positive = s1> 0 || s2 > 0 || s3 > 0;
  return !(negative && positive);
}

TriangleBox::TriangleBox(const Triangle& t) {
  lo = {std::min({t.p[0].x, t.p[1].x, t.p[2].x}), std::min({t.p[0].y, t.p[1].y, t.p[2].y}),
        std::min({t.p[0].z, t.p[1].z, t.p[2].z})};
  hi = {std::max({t.p[0].x, t.p[1].x, t.p[2].x}), std::max({t.p[0].y, t.p[1].y, t.p[2].y}),
        std::max({t.p[0].z, t.p[1].z, t.p[2].z})};
  const double slack = 1e-9 * (std::fabs(lo.x) + std::fabs(lo.y) + std::fabs(lo.z) +
                               std::fabs(hi.x) + std::fabs(hi.y) + std::fabs(hi.z) + 1e-30);
  lo = lo - DVec3{slack, slack, slack};
  hi = hi + DVec3{slack, slack, slack};
}

bool TrianglesIntersect(const Triangle& a, const Triangle& b) {
  return TriangleBox(a).Overlaps(TriangleBox(b)) && reference::OverlappingTrianglesIntersect(a, b);
}

bool OverlappingTrianglesIntersect(const Triangle& a, const Triangle& b) {
  int shared = 0, ia[3], ib[3];  // ia[k], ib[k]: corners of a and b that are the same vertex
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.id[i] == b.id[j]) {
        ia[shared] = i;
        ib[shared++] = j;
      }
  if (shared == 3) return true;  // the same triangle twice
  if (shared == 2) {
    // They meet along the shared edge; beyond it only if they fold onto each other.
    const DVec3 &p = a.p[ia[0]], &q = a.p[ia[1]];
    const DVec3& r = a.p[3 - ia[0] - ia[1]];
    const DVec3& s = b.p[3 - ib[0] - ib[1]];
    if (Orient3d(p, q, r, s) != 0) return false;
    const Projection flat(Cross(q - p, r - p));
    const int sr = Orient2d(flat(p), flat(q), flat(r)), ss = Orient2d(flat(p), flat(q), flat(s));
    return sr * ss >= 0;
  }
  if (shared == 1) {
    // Beyond the shared corner, they meet iff the edge opposite it in one meets the other.
    const int i = ia[0], j = ib[0];
    return MeetsTriangle(a.p[(i + 1) % 3], a.p[(i + 2) % 3], b) ||
           MeetsTriangle(b.p[(j + 1) % 3], b.p[(j + 2) % 3], a);
  }
  // Two triangles that meet have an edge of one meeting the other.
  for (int k = 0; k < 3; ++k)
    if (MeetsTriangle(a.p[k], a.p[(k + 1) % 3], b) || MeetsTriangle(b.p[k], b.p[(k + 1) % 3], a))
      return true;
  return false;
}

}  // namespace reference
namespace {

class Lattice {
 public:
  explicit Lattice(uint32_t seed) : rng_(seed) {}
  // A point on a lattice of step 1/4 in [-2, 2]^3, sometimes nudged off it by a float ulp or by
  // a tiny relative amount, then rounded to float as mesh positions are.
  DVec3 Point() {
    DVec3 p{Step(), Step(), Step()};
    const int nudge = Int(0, 9);
    if (nudge == 0) p.z = std::nextafter(static_cast<float>(p.z), 10.0f);
    if (nudge == 1) p.x += 1e-7 * (Int(0, 1) ? 1 : -1);
    if (nudge == 2) p = {p.x * 1000 + 5000, p.y * 1000, p.z * 1000};  // far from the origin
    return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  }
  DVec3 FlatPoint() {  // in the plane z = 0.5 (coplanar pairs)
    DVec3 p = Point();
    p.z = 0.5;
    return p;
  }
  DVec3 TinyPoint() {  // a 4 x 4 lattice in a tilted plane: ties and collinear corners galore
    const double u = Int(0, 3), v = Int(0, 3);
    return {u, v, 0.5 * u + 0.25 * v};
  }
  int Int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

 private:
  double Step() { return 0.25 * Int(-8, 8); }
  std::mt19937 rng_;
};

Triangle RandomPair(Lattice& l, Triangle* other) {
  const int kind = l.Int(0, 2);  // 0: anywhere, 1: one plane, 2: one small lattice in a plane
  auto point = [&] { return kind == 0 ? l.Point() : kind == 1 ? l.FlatPoint() : l.TinyPoint(); };
  Triangle a, b;
  for (int k = 0; k < 3; ++k) {
    a.p[k] = point();
    b.p[k] = point();
    a.id[k] = k;
    b.id[k] = 3 + k;
  }
  // Share 0 to 3 corners (the same vertex: same id and position), in any order.
  const int shared = l.Int(0, 3);
  for (int s = 0; s < shared; ++s) {
    const int i = s, j = (s + l.Int(0, 2)) % 3;
    if (b.id[j] < 3) continue;
    b.p[j] = a.p[i];
    b.id[j] = a.id[i];
  }
  *other = b;
  return a;
}

TEST(PreparedTriangleTests, MatchThePlainOnes) {
  Lattice lattice(12);
  int hits = 0, overlapping = 0;
  for (int n = 0; n < 400000; ++n) {
    Triangle b;
    const Triangle a = RandomPair(lattice, &b);
    const bool expected = reference::TrianglesIntersect(a, b);
    ASSERT_EQ(TrianglesIntersect(a, b), expected) << "pair " << n;
    const PreparedTriangle pa(a), pb(b);
    const reference::TriangleBox ra(a), rb(b);
    for (double DVec3::*k : {&DVec3::x, &DVec3::y, &DVec3::z}) {
      ASSERT_EQ(pa.box.lo.*k, ra.lo.*k);
      ASSERT_EQ(pa.box.hi.*k, ra.hi.*k);
    }
    ASSERT_EQ(pa.box.Overlaps(pb.box), ra.Overlaps(rb));
    if (ra.Overlaps(rb)) {
      ++overlapping;
      ASSERT_EQ(OverlappingTrianglesIntersect(pa, pb),
                reference::OverlappingTrianglesIntersect(a, b))
          << "pair " << n;
      ASSERT_EQ(OverlappingTrianglesIntersect(pb, pa),
                reference::OverlappingTrianglesIntersect(b, a))
          << "pair " << n;
    }
    for (int k = 0; k < 3; ++k) {
      const DVec3 &p = b.p[k], &q = b.p[(k + 1) % 3];
      ASSERT_EQ(SegmentMeetsTriangle(p, q, a.p[0], a.p[1], a.p[2]),
                reference::SegmentMeetsTriangle(p, q, a.p[0], a.p[1], a.p[2]))
          << "pair " << n;
    }
    hits += expected;
  }
  // Both answers come often enough for the comparison to mean something.
  EXPECT_GT(hits, 40000);
  EXPECT_GT(overlapping - hits, 40000);
}

// A flat region of a CAD part: triangles in one plane far from the origin (CAD flats are planes
// the float corners lie on exactly: one at z = 40, and a tilted one on a dyadic grid), sharing a
// corner or none, at every angle and size ratio. Such pairs are decided in the plane
// (ClearlyApartInTheirPlane and its shared-corner form) wherever a line separates them clearly:
// the answer must be the plain tests' on every pair.
TEST(PreparedTriangleTests, MatchThePlainOnesInAPlane) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  bool tilted = false;
  auto in_plane = [&](double u, double v) {
    if (!tilted) return DVec3{static_cast<float>(1000 + u), static_cast<float>(-250 + v), 40.0};
    const double x = 1000 + std::round(u * 4096) / 4096, y = -250 + std::round(v * 4096) / 4096;
    return DVec3{x, y, 0.5 * x + 0.25 * y};  // exact in float
  };
  auto around = [&](double u, double v) {  // a corner at a random angle and distance
    const double angle = 2 * M_PI * unit(rng), r = std::pow(10.0, -2 * unit(rng));
    return in_plane(u + r * std::cos(angle), v + r * std::sin(angle));
  };
  int hits = 0, misses = 0;
  for (int n = 0; n < 200000; ++n) {
    tilted = n % 2 == 1;
    const double u = unit(rng), v = unit(rng);
    Triangle a{{in_plane(u, v), around(u, v), around(u, v)}, {0, 1, 2}};
    Triangle b{{a.p[0], around(u, v), around(u, v)}, {0, 4, 5}};
    if (n % 5 == 0) {  // no corner shared
      b.p[0] = around(u, v);
      b.id[0] = 3;
    }
    std::rotate(b.p, b.p + n % 3, b.p + 3);  // the shared corner at any place
    std::rotate(b.id, b.id + n % 3, b.id + 3);
    const bool expected = reference::TrianglesIntersect(a, b);
    ASSERT_EQ(TrianglesIntersect(a, b), expected) << "pair " << n;
    ASSERT_EQ(TrianglesIntersect(b, a), reference::TrianglesIntersect(b, a)) << "pair " << n;
    (expected ? hits : misses) += 1;
  }
  EXPECT_GT(hits, 20000);
  EXPECT_GT(misses, 20000);
}

}  // namespace
}  // namespace femsimp
