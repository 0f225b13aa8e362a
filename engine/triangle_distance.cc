#include "engine/triangle_distance.h"

#include <algorithm>

namespace femsimp {

double SquaredDistanceToSegment(const DVec3& q, const DVec3& a, const DVec3& b) {
  const DVec3 ab = b - a;
  const double len2 = Dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(Dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
  const DVec3 d = q - (a + t * ab);
  return Dot(d, d);
}

double SquaredDistanceToTriangle(const DVec3& q, const DVec3& a, const DVec3& b, const DVec3& c) {
  // The closest point by Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5); every
  // branch returns the distance to a point of the triangle, so rounding never makes it smaller
  // than the exact distance by more than a few ulps.
  const DVec3 ab = b - a, ac = c - a, ap = q - a;
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return Dot(ap, ap);
  const DVec3 bp = q - b;
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return Dot(bp, bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return SquaredDistanceToSegment(q, a, b);
  const DVec3 cp = q - c;
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return Dot(cp, cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return SquaredDistanceToSegment(q, a, c);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return SquaredDistanceToSegment(q, b, c);
  const double sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate: the nearest of its edges
    return std::min({SquaredDistanceToSegment(q, a, b), SquaredDistanceToSegment(q, b, c),
                     SquaredDistanceToSegment(q, c, a)});
  }
  const double v = vb / sum, w = vc / sum;
  const DVec3 d = q - (a + v * ab + w * ac);
  return Dot(d, d);
}

}  // namespace femsimp
