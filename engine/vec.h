// Double-precision 3-vectors for the geometric tests (positions are stored as floats).
#pragma once

#include <cmath>

#include "engine/ring.h"

namespace femsimp {

struct DVec3 {
  double x, y, z;
};

inline DVec3 operator+(const DVec3& a, const DVec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline DVec3 operator-(const DVec3& a, const DVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DVec3 operator*(double s, const DVec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline DVec3& operator+=(DVec3& a, const DVec3& b) { return a = a + b; }
inline DVec3& operator-=(DVec3& a, const DVec3& b) { return a = a - b; }
inline double Dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline DVec3 Cross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double Norm(const DVec3& a) { return std::sqrt(Dot(a, a)); }
inline DVec3 ToD(const Vec3& v) { return {v.x, v.y, v.z}; }

// d as the mesh stores it (each coordinate rounded to a float), for judging a new position
// where it will be. Each float passes through memory the optimizer cannot see into: GCC 12's
// SLP vectorizer (at -O2 and -O3) turned ToD(Vec3{float(d.x), float(d.y), float(d.z)}) into
// d.x and d.y unrounded, so the rules judged a point the mesh never held (far from the origin,
// where floats are far apart, by a good part of the tolerance).
inline Vec3 StoredPosition(const DVec3& d) {
  Vec3 v{static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)};
#if defined(__GNUC__)
  asm("" : "+m"(v));
#endif
  return v;
}

}  // namespace femsimp
