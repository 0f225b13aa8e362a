// Whether two triangles of a surface mesh intersect beyond what they share. Closed sets, with
// a relative tolerance on the orientation tests: near-touching counts as touching, so a
// collapse refused on it errs on the safe side. Triangles that share an edge or a vertex meet
// there by construction; that contact is not an intersection. A separating plane settles it
// first: a triangle whose corners (beyond a shared one) lie strictly on one side of the
// other's plane, beyond the same relative margin, is apart from it; coplanar triangles that a
// line in their plane separates by far more than that margin are apart too.
#pragma once

#include <cstdint>

#include "engine/vec.h"

namespace femsimp {

struct Triangle {
  DVec3 p[3];
  uint32_t id[3];  // vertex ids: equal ids are shared corners
};

// A triangle's bounding box, widened by a relative slack so that touching boxes overlap.
struct TriangleBox {
  DVec3 lo, hi;
  TriangleBox() = default;
  explicit TriangleBox(const Triangle& t);
  // The same box from the triangle's exact corner minima and maxima.
  TriangleBox(const DVec3& min, const DVec3& max);
  bool Overlaps(const TriangleBox& o) const {
    return !(lo.x > o.hi.x || o.lo.x > hi.x || lo.y > o.hi.y || o.lo.y > hi.y || lo.z > o.hi.z ||
             o.lo.z > hi.z);
  }
};

// A triangle with what every test against it derives from it alone, computed once: a triangle
// is tested against dozens of others per collapse. The tests below compute exactly what the
// plain ones compute (the same operations in the same order), only not again.
struct PreparedTriangle {
  Triangle t;
  TriangleBox box;
  DVec3 normal;        // Cross(p1 - p0, p2 - p0), unnormalised
  double scale2;       // |p1 - p0|^2 |p2 - p0|^2, the scale of the orientation test
  double reach_lo[3];  // per axis: a segment below this (or above reach_hi) misses the triangle
  double reach_hi[3];
  // Its height over its longest edge is above 1e-9 of that edge: its plane is sharp enough for
  // a side test to separate (the degenerate rule keeps new triangles far above this).
  bool well_shaped;
  PreparedTriangle() = default;
  explicit PreparedTriangle(const Triangle& triangle);
};

bool TrianglesIntersect(const Triangle& a, const Triangle& b);
// The same, for triangles whose boxes are known to overlap.
bool OverlappingTrianglesIntersect(const Triangle& a, const Triangle& b);
bool OverlappingTrianglesIntersect(const PreparedTriangle& a, const PreparedTriangle& b);

// The closed segment pq meets the closed triangle abc.
bool SegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                          const DVec3& c);

}  // namespace femsimp
