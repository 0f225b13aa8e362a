// Whether two triangles of a surface mesh intersect beyond what they share. Closed sets, with
// a relative tolerance on the orientation tests: near-touching counts as touching, so a
// collapse refused on it errs on the safe side. Triangles that share an edge or a vertex meet
// there by construction; that contact is not an intersection.
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
  explicit TriangleBox(const Triangle& t);
  bool Overlaps(const TriangleBox& o) const {
    return !(lo.x > o.hi.x || o.lo.x > hi.x || lo.y > o.hi.y || o.lo.y > hi.y || lo.z > o.hi.z ||
             o.lo.z > hi.z);
  }
};

bool TrianglesIntersect(const Triangle& a, const Triangle& b);
// The same, for triangles whose boxes are known to overlap.
bool OverlappingTrianglesIntersect(const Triangle& a, const Triangle& b);

// The closed segment pq meets the closed triangle abc.
bool SegmentMeetsTriangle(const DVec3& p, const DVec3& q, const DVec3& a, const DVec3& b,
                          const DVec3& c);

}  // namespace femsimp
