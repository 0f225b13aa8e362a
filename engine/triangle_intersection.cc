#include "engine/triangle_intersection.h"

#include <algorithm>
#include <cmath>

namespace femsimp {
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

// The corners' minima and maxima per axis.
void Extent(const Triangle& t, DVec3* min, DVec3* max) {
  *min = {std::min({t.p[0].x, t.p[1].x, t.p[2].x}), std::min({t.p[0].y, t.p[1].y, t.p[2].y}),
          std::min({t.p[0].z, t.p[1].z, t.p[2].z})};
  *max = {std::max({t.p[0].x, t.p[1].x, t.p[2].x}), std::max({t.p[0].y, t.p[1].y, t.p[2].y}),
          std::max({t.p[0].z, t.p[1].z, t.p[2].z})};
}

// Sign of the volume of (a, b, c, d).
int Orient3d(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d) {
  const DVec3 u = b - a, v = c - a, w = d - a;
  return Sign(Dot(Cross(u, v), w), Dot(u, u) * Dot(v, v) * Dot(w, w));
}

// Orient3d(t.p[0], t.p[1], t.p[2], d): the side of t's plane d lies on.
int PlaneSide(const PreparedTriangle& t, const DVec3& d) {
  const DVec3 w = d - t.t.p[0];
  return Sign(Dot(t.normal, w), t.scale2 * Dot(w, w));
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

// Signs on both sides of zero among s[0..2]: a point outside a triangle (either orientation).
bool Mixed(const int s[3]) {
  const bool negative = s[0] < 0 || s[1] < 0 || s[2] < 0;
  const bool positive = s[0] > 0 || s[1] > 0 || s[2] > 0;
  return negative && positive;
}

// side[i] = Orient2d(c[i], c[i + 1], p): p's side of each edge of the 2D triangle c.
void EdgeSides(const P2 c[3], const P2& p, int side[3]) {
  for (int i = 0; i < 3; ++i) side[i] = Orient2d(c[i], c[(i + 1) % 3], p);
}

// Closed 2D segment pq against the closed 2D triangle c (either orientation), given the sides
// of p and q of its edges (EdgeSides): p or q in the triangle, or pq meeting one of its closed
// edges. The point tests and the edge tests share those orientations.
bool SegmentMeetsTriangle2d(const P2& p, const P2& q, const P2 c[3], const int side_p[3],
                            const int side_q[3]) {
  if (!Mixed(side_p) || !Mixed(side_q)) return true;
  int line[3];  // line[i]: Orient2d(p, q, c[i])
  for (int i = 0; i < 3; ++i) line[i] = Orient2d(p, q, c[i]);
  for (int i = 0; i < 3; ++i) {  // closed segments pq and c[i] c[i + 1]
    const P2 &a = c[i], &b = c[(i + 1) % 3];
    const int o1 = line[i], o2 = line[(i + 1) % 3], o3 = side_p[i], o4 = side_q[i];
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    if ((o1 == 0 && OnSegment(a, p, q)) || (o2 == 0 && OnSegment(b, p, q)) ||
        (o3 == 0 && OnSegment(p, a, b)) || (o4 == 0 && OnSegment(q, a, b)))
      return true;
  }
  return false;
}

// Segment pq in the plane of triangle abc (normal n = Cross(b - a, c - a)).
bool CoplanarSegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                                  const DVec3& c, const DVec3& n) {
  const Projection flat(n);
  const P2 corners[3] = {flat(a), flat(b), flat(c)};
  const P2 p2 = flat(p), q2 = flat(q);
  int side_p[3], side_q[3];
  EdgeSides(corners, p2, side_p);
  if (!Mixed(side_p)) return true;
  EdgeSides(corners, q2, side_q);
  return SegmentMeetsTriangle2d(p2, q2, corners, side_p, side_q);
}

// The line pq crosses the plane of abc inside the segment: it meets the triangle iff it passes
// on the same side of all three edges (or along one).
bool CrossingMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                           const DVec3& c) {
  // Orient3d(p, q, x, y) for the edges xy of abc, sharing q - p and the corners' offsets.
  const DVec3 u = q - p, da = a - p, db = b - p, dc = c - p;
  const double uu = Dot(u, u), aa = Dot(da, da), bb = Dot(db, db), cc = Dot(dc, dc);
  const int s[3] = {Sign(Dot(Cross(u, da), db), uu * aa * bb),
                    Sign(Dot(Cross(u, db), dc), uu * bb * cc),
                    Sign(Dot(Cross(u, dc), da), uu * cc * aa)};
  return !Mixed(s);
}

// Whether pq reaches t's box along every axis (SegmentMeetsTriangle's first rejection).
bool Reaches(const DVec3& p, const DVec3& q, const PreparedTriangle& t) {
  return !(std::max(p.x, q.x) < t.reach_lo[0] || std::min(p.x, q.x) > t.reach_hi[0] ||
           std::max(p.y, q.y) < t.reach_lo[1] || std::min(p.y, q.y) > t.reach_hi[1] ||
           std::max(p.z, q.z) < t.reach_lo[2] || std::min(p.z, q.z) > t.reach_hi[2]);
}

// SegmentMeetsTriangle(p, q, t's corners), given the sides of p and q of t's plane.
bool SegmentMeets(const DVec3& p, const DVec3& q, int sp, int sq, const PreparedTriangle& t) {
  if (sp == sq && sp != 0) return false;
  const DVec3* c = t.t.p;
  if (sp == 0 && sq == 0) return CoplanarSegmentMeetsTriangle(p, q, c[0], c[1], c[2], t.normal);
  return CrossingMeetsTriangle(p, q, c[0], c[1], c[2]);
}

bool SegmentMeets(const DVec3& p, const DVec3& q, const PreparedTriangle& t) {
  return Reaches(p, q, t) && SegmentMeets(p, q, PlaneSide(t, p), PlaneSide(t, q), t);
}

// SegmentMeets for each edge of s against t, given the sides of s's corners of t's plane. In
// the plane, the sides of s's corners of t's edges serve two edges each: computed once.
bool EdgesMeet(const PreparedTriangle& s, const int side[3], const PreparedTriangle& t) {
  Projection flat(t.normal);
  P2 corners[3], s2[3];
  int sides2[3][3];
  bool flat_ready = false, sides2_ready[3] = {false, false, false};
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    const DVec3 &p = s.t.p[k], &q = s.t.p[l];
    if (!Reaches(p, q, t) || (side[k] == side[l] && side[k] != 0)) continue;
    if (side[k] != 0 || side[l] != 0) {
      if (CrossingMeetsTriangle(p, q, t.t.p[0], t.t.p[1], t.t.p[2])) return true;
      continue;
    }
    if (!flat_ready) {
      for (int i = 0; i < 3; ++i) corners[i] = flat(t.t.p[i]);
      flat_ready = true;
    }
    for (const int m : {k, l}) {
      if (sides2_ready[m]) continue;
      s2[m] = flat(s.t.p[m]);
      EdgeSides(corners, s2[m], sides2[m]);
      sides2_ready[m] = true;
    }
    if (SegmentMeetsTriangle2d(s2[k], s2[l], corners, sides2[k], sides2[l])) return true;
  }
  return false;
}

double Cross2(const P2& u, const P2& v) { return u.x * v.y - u.y * v.x; }
P2 Minus(const P2& a, const P2& b) { return {a.x - b.x, a.y - b.y}; }

// Twice the signed area of a 2D triangle.
double Area2(const P2 t[3]) { return Cross2(Minus(t[1], t[0]), Minus(t[2], t[0])); }

// A line along an edge of s (2D, twice its signed area s_area2) with s on one side and every
// corner of o at least margin / |edge| beyond it on the other.
bool AnEdgeSeparates(const P2 s[3], double s_area2, const P2 o[3], double margin) {
  const double inward = s_area2 > 0 ? 1.0 : -1.0;
  for (int k = 0; k < 3; ++k) {
    const P2 edge = Minus(s[(k + 1) % 3], s[k]);
    bool separates = true;
    for (int i = 0; i < 3 && separates; ++i)
      separates = inward * Cross2(edge, Minus(o[i], s[k])) <= -margin;
    if (separates) return true;
  }
  return false;
}

// How clear ClearlyApartInTheirPlane wants it, relative to the longest edge L of the two.
constexpr double kClearlyApart = 1e-3;

// Triangles that share no corner and whose corners all lie within the near-touch band of each
// other's plane (a flat region: most pairs the rule tests on a CAD part), separated in that
// plane by a line along an edge of one, clearly: the other's corners at least kClearlyApart·L
// beyond it, and both triangles at least as thick. Then the two are more than kClearlyApart²·L/8
// apart (beyond their shared corner, in the form below that shares one), and tilted from each other
// by less than 1e-9: a gap that no sign the plain tests take (each zero only within 1e-12 of its
// lengths) can close, so they would answer "apart" too, at several times this cost. (A projection
// never separates what meets, so this is sound whatever the plane's accuracy.)
bool ClearlyApartInTheirPlane(const PreparedTriangle& a, const PreparedTriangle& b) {
  const Projection flat(a.normal);
  P2 pa[3], pb[3];
  double longest2 = 0;
  for (int k = 0; k < 3; ++k) {
    pa[k] = flat(a.t.p[k]);
    pb[k] = flat(b.t.p[k]);
  }
  for (int k = 0; k < 3; ++k) {
    const P2 ea = Minus(pa[(k + 1) % 3], pa[k]), eb = Minus(pb[(k + 1) % 3], pb[k]);
    longest2 = std::max({longest2, ea.x * ea.x + ea.y * ea.y, eb.x * eb.x + eb.y * eb.y});
  }
  const double margin = kClearlyApart * longest2;
  const double area_a = Area2(pa), area_b = Area2(pb);
  if (!(std::fabs(area_a) > margin && std::fabs(area_b) > margin)) return false;
  return AnEdgeSeparates(pa, area_a, pb, margin) || AnEdgeSeparates(pb, area_b, pa, margin);
}

// ClearlyApartInTheirPlane for triangles that share exactly the corner a.p[i] = b.p[j]: only a
// line through it can separate them, along one of the four edges there.
bool ClearlyApartAtSharedCorner(const PreparedTriangle& a, int i, const PreparedTriangle& b,
                                int j) {
  const Projection flat(a.normal);
  const P2 oa = flat(a.t.p[i]), ob = flat(b.t.p[j]);
  const P2 u1 = Minus(flat(a.t.p[(i + 1) % 3]), oa), u2 = Minus(flat(a.t.p[(i + 2) % 3]), oa);
  const P2 w1 = Minus(flat(b.t.p[(j + 1) % 3]), ob), w2 = Minus(flat(b.t.p[(j + 2) % 3]), ob);
  const auto length2 = [](const P2& v) { return v.x * v.x + v.y * v.y; };
  const double margin =
      kClearlyApart * std::max({length2(u1), length2(u2), length2(Minus(u2, u1)), length2(w1),
                                length2(w2), length2(Minus(w2, w1))});
  const double area_a = Cross2(u1, u2), area_b = Cross2(w1, w2);
  if (!(std::fabs(area_a) > margin && std::fabs(area_b) > margin)) return false;
  // The line along `edge` has the edge's own triangle on the side `inward`, c and d beyond it.
  const auto beyond = [margin](const P2& edge, double inward, const P2& c, const P2& d) {
    return inward * Cross2(edge, c) <= -margin && inward * Cross2(edge, d) <= -margin;
  };
  const double side_a = area_a > 0 ? 1.0 : -1.0, side_b = area_b > 0 ? 1.0 : -1.0;
  return beyond(u1, side_a, w1, w2) || beyond(u2, -side_a, w1, w2) || beyond(w1, side_b, u1, u2) ||
         beyond(w2, -side_b, u1, u2);
}

// Corners all strictly on one side of the other's plane.
bool Apart(const int side[3]) { return side[0] != 0 && side[0] == side[1] && side[1] == side[2]; }

// Neither triangle shares a corner with the other: they meet iff an edge of one meets the
// other. The side of each corner of one of the other's plane serves two edges: computed once.
bool DisjointCornersIntersect(const PreparedTriangle& a, const PreparedTriangle& b) {
  int side_a[3], side_b[3];  // side_a[k]: a's corner k of b's plane; side_b[k]: b's of a's
  // A triangle strictly on one side of the other's plane cannot meet it: most pairs a collapse
  // tests end here, after three or six dot products.
  const bool sharp = a.well_shaped && b.well_shaped;
  for (int k = 0; k < 3; ++k) side_a[k] = PlaneSide(b, a.t.p[k]);
  const bool a_apart = Apart(side_a);
  if (sharp && a_apart) return false;
  for (int k = 0; k < 3; ++k) side_b[k] = PlaneSide(a, b.t.p[k]);
  const bool b_apart = Apart(side_b);
  if (sharp && b_apart) return false;
  if (side_a[0] == 0 && side_a[1] == 0 && side_a[2] == 0 && side_b[0] == 0 && side_b[1] == 0 &&
      side_b[2] == 0 && ClearlyApartInTheirPlane(a, b))
    return false;
  // A triangle apart has no edge that meets the other (each has both ends on one side).
  return (!a_apart && EdgesMeet(a, side_a, b)) || (!b_apart && EdgesMeet(b, side_b, a));
}

// a and b share exactly the corner a.p[i] = b.p[j]. Beyond it, they meet iff the edge opposite
// it in one meets the other. One's opposite corners strictly on one side of the other's plane:
// it touches that plane at the shared corner only, so neither edge meets.
bool OneCornerIntersect(const PreparedTriangle& a, int i, const PreparedTriangle& b, int j) {
  const DVec3 &p = a.t.p[(i + 1) % 3], &q = a.t.p[(i + 2) % 3];
  const bool sharp = a.well_shaped && b.well_shaped;
  const int sp = PlaneSide(b, p), sq = PlaneSide(b, q);
  if (sharp && sp == sq && sp != 0) return false;
  const DVec3 &r = b.t.p[(j + 1) % 3], &s = b.t.p[(j + 2) % 3];
  const int sr = PlaneSide(a, r), ss = PlaneSide(a, s);
  if (sharp && sr == ss && sr != 0) return false;
  if (sp == 0 && sq == 0 && sr == 0 && ss == 0 && ClearlyApartAtSharedCorner(a, i, b, j))
    return false;
  return (Reaches(p, q, b) && SegmentMeets(p, q, sp, sq, b)) ||
         (Reaches(r, s, a) && SegmentMeets(r, s, sr, ss, a));
}

}  // namespace

bool SegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                          const DVec3& c) {
  return SegmentMeets(p, q, PreparedTriangle(Triangle{{a, b, c}, {0, 0, 0}}));
}

TriangleBox::TriangleBox(const DVec3& min, const DVec3& max) : lo(min), hi(max) {
  const double slack = 1e-9 * (std::fabs(lo.x) + std::fabs(lo.y) + std::fabs(lo.z) +
                               std::fabs(hi.x) + std::fabs(hi.y) + std::fabs(hi.z) + 1e-30);
  lo = lo - DVec3{slack, slack, slack};
  hi = hi + DVec3{slack, slack, slack};
}

TriangleBox::TriangleBox(const Triangle& t) {
  DVec3 min, max;
  Extent(t, &min, &max);
  *this = TriangleBox(min, max);
}

PreparedTriangle::PreparedTriangle(const Triangle& triangle) : t(triangle) {
  DVec3 min, max;
  Extent(t, &min, &max);
  box = TriangleBox(min, max);
  const DVec3 u = t.p[1] - t.p[0], v = t.p[2] - t.p[0];
  normal = Cross(u, v);
  scale2 = Dot(u, u) * Dot(v, v);
  const DVec3 w = t.p[2] - t.p[1];
  const double longest2 = std::max({Dot(u, u), Dot(v, v), Dot(w, w)});
  well_shaped = Dot(normal, normal) > 1e-18 * longest2 * longest2;
  const double lo[3] = {min.x, min.y, min.z}, hi[3] = {max.x, max.y, max.z};
  for (int a = 0; a < 3; ++a) {
    const double slack = 1e-9 * (std::fabs(lo[a]) + std::fabs(hi[a]));
    reach_lo[a] = lo[a] - slack;
    reach_hi[a] = hi[a] + slack;
  }
}

bool TrianglesIntersect(const Triangle& a, const Triangle& b) {
  return TriangleBox(a).Overlaps(TriangleBox(b)) && OverlappingTrianglesIntersect(a, b);
}

bool OverlappingTrianglesIntersect(const Triangle& a, const Triangle& b) {
  return OverlappingTrianglesIntersect(PreparedTriangle(a), PreparedTriangle(b));
}

bool OverlappingTrianglesIntersect(const PreparedTriangle& pa, const PreparedTriangle& pb) {
  const Triangle &a = pa.t, &b = pb.t;
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
  if (shared == 1) return OneCornerIntersect(pa, ia[0], pb, ib[0]);
  // Two triangles that meet have an edge of one meeting the other.
  return DisjointCornersIntersect(pa, pb);
}

}  // namespace femsimp
