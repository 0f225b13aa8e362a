#include "engine/inertia.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace femsimp {

Sym3& Sym3::operator+=(const Sym3& o) {
  xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, yz += o.yz, zx += o.zx;
  return *this;
}

Sym3& Sym3::operator-=(const Sym3& o) {
  xx -= o.xx, yy -= o.yy, zz -= o.zz, xy -= o.xy, yz -= o.yz, zx -= o.zx;
  return *this;
}

Sym3 operator+(Sym3 a, const Sym3& b) { return a += b; }
Sym3 operator-(Sym3 a, const Sym3& b) { return a -= b; }
Sym3 operator*(double s, const Sym3& a) {
  return {s * a.xx, s * a.yy, s * a.zz, s * a.xy, s * a.yz, s * a.zx};
}

Sym3 Outer(const DVec3& a) {
  return {a.x * a.x, a.y * a.y, a.z * a.z, a.x * a.y, a.y * a.z, a.z * a.x};
}

Sym3 SymmetricProduct(const DVec3& a, const DVec3& b) {
  return {2 * a.x * b.x,         2 * a.y * b.y,         2 * a.z * b.z,
          a.x * b.y + a.y * b.x, a.y * b.z + a.z * b.y, a.z * b.x + a.x * b.z};
}

Sym3 TetrahedronSecondMoment(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d,
                             double volume) {
  return (volume / 20.0) * (Outer(a) + Outer(b) + Outer(c) + Outer(d) + Outer(a + b + c + d));
}

Sym3 TriangleSecondMoment(const DVec3& a, const DVec3& b, const DVec3& c, double area) {
  return (area / 12.0) * (Outer(a) + Outer(b) + Outer(c) + Outer(a + b + c));
}

Sym3 InertiaOf(const Sym3& j) {
  const double t = j.trace();
  return {t - j.xx, t - j.yy, t - j.zz, -j.xy, -j.yz, -j.zx};
}

Eigen3 Eigen(const Sym3& s) {
  double a[3][3] = {{s.xx, s.xy, s.zx}, {s.xy, s.yy, s.yz}, {s.zx, s.yz, s.zz}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 64; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (!(off > 1e-32 * diag)) break;  // also ends on a zero or non-finite tensor
    for (const auto& [p, q] : kPairs) {
      if (a[p][q] == 0.0) continue;
      // The rotation in the (p, q) plane that zeroes a[p][q] (the smaller of the two angles).
      const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
      const double t = std::fabs(theta) > 1e150 ? 0.5 / theta
                                                : std::copysign(1.0, theta) /
                                                      (std::fabs(theta) + std::hypot(theta, 1.0));
      const double c = 1.0 / std::sqrt(t * t + 1.0), sn = t * c;
      for (int k = 0; k < 3; ++k) {
        const double kp = a[k][p], kq = a[k][q];
        a[k][p] = c * kp - sn * kq;
        a[k][q] = sn * kp + c * kq;
      }
      for (int k = 0; k < 3; ++k) {
        const double pk = a[p][k], qk = a[q][k];
        a[p][k] = c * pk - sn * qk;
        a[q][k] = sn * pk + c * qk;
      }
      a[p][q] = a[q][p] = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double kp = v[k][p], kq = v[k][q];
        v[k][p] = c * kp - sn * kq;
        v[k][q] = sn * kp + c * kq;
      }
    }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int i, int j) { return a[i][i] < a[j][j]; });
  Eigen3 e;
  for (int i = 0; i < 3; ++i) {
    const int k = order[i];
    e.values[i] = a[k][k];
    e.axes[i] = {v[0][k], v[1][k], v[2][k]};
  }
  return e;
}

double PrincipalMomentChange(const MassSummary& before, const MassSummary& after) {
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double reference = std::fabs(before.principal_moments[i]);
    if (reference > 0.0)
      worst = std::max(
          worst, std::fabs(after.principal_moments[i] - before.principal_moments[i]) / reference);
  }
  return worst;
}

}  // namespace femsimp
