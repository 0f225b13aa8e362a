#include "engine/star.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace femsimp {

bool EdgeStar::Build(const Ring& fan, int target, const Ring& target_fan, int line_other) {
  const int n = fan.neighbours();
  const uint32_t v = fan.center, vd = fan.nbr[target];
  const DVec3 pv = ToD(fan.center_pos), pd = ToD(fan.pos[target]);
  on_line = line_other >= 0;
  if (on_line) {
    line_v_end = ToD(fan.pos[line_other]);
    int end = -1;
    for (int i = 0; i < target_fan.neighbours(); ++i)
      if (target_fan.feature[i] && target_fan.nbr[i] != v) end = i;
    if (end < 0) return false;
    line_vd_end = ToD(target_fan.pos[end]);
  }
  count = 0;
  vd_id = vd;
  this->v = pv;
  this->vd = pd;
  lo = hi = pv;
  const auto grow = [this](const DVec3& q) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  };
  if (fan.faces > kMaxStar) return false;
  for (int f = 0; f < fan.faces; ++f) {
    const int g = (f + 1) % n;
    a[count] = pv;
    b[count] = ToD(fan.pos[f]);
    c[count] = ToD(fan.pos[g]);
    survives[count] = fan.nbr[f] != vd && fan.nbr[g] != vd;
    face[count] = FaceOf(fan.out[f]);
    a_id[count] = v;
    b_id[count] = fan.nbr[f];
    c_id[count] = fan.nbr[g];
    grow(b[count]);
    ++count;
  }
  fan_faces = count;
  const int m = target_fan.neighbours();
  for (int f = 0; f < target_fan.faces; ++f) {
    const int g = (f + 1) % m;
    if (target_fan.nbr[f] == v || target_fan.nbr[g] == v) continue;  // on V - Vd: V's already
    if (count == kMaxStar) return false;
    a[count] = pd;
    b[count] = ToD(target_fan.pos[f]);
    c[count] = ToD(target_fan.pos[g]);
    survives[count] = true;
    face[count] = FaceOf(target_fan.out[f]);
    a_id[count] = vd;
    b_id[count] = target_fan.nbr[f];
    c_id[count] = target_fan.nbr[g];
    grow(b[count]);
    grow(c[count]);
    ++count;
  }
  WidenForPlacement(&lo, &hi);
  return true;
}

namespace {

// Solves the n x n system m x = r (n <= 4) by Gaussian elimination with partial pivoting;
// false when a pivot is negligible against the matrix's scale.
bool Solve(int n, double m[4][4], double r[4], double x[4]) {
  double scale = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) scale = std::max(scale, std::fabs(m[i][j]));
  if (!(scale > 0.0)) return false;
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int i = col + 1; i < n; ++i)
      if (std::fabs(m[i][col]) > std::fabs(m[pivot][col])) pivot = i;
    if (!(std::fabs(m[pivot][col]) > 1e-12 * scale)) return false;
    std::swap(m[pivot], m[col]);
    std::swap(r[pivot], r[col]);
    for (int i = col + 1; i < n; ++i) {
      const double f = m[i][col] / m[col][col];
      for (int j = col; j < n; ++j) m[i][j] -= f * m[col][j];
      r[i] -= f * r[col];
    }
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = r[i];
    for (int j = i + 1; j < n; ++j) s -= m[i][j] * x[j];
    x[i] = s / m[i][i];
  }
  return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

// Sum over the surviving faces of b x c, and six times the old volume under the star, both
// relative to `mid`: the new volume under the star is (p - mid) . normal_sum / 6.
struct VolumeTerms {
  DVec3 normal_sum{0, 0, 0};
  double old_volume6 = 0.0;
  double area2 = 0.0;
  // Whether the plane of the points that keep the volume is defined (not a star folded shut).
  bool defined() const { return Norm(normal_sum) > 1e-6 * area2; }
};
VolumeTerms VolumeTermsOf(const EdgeStar& star, const DVec3& mid) {
  VolumeTerms t;
  for (int k = 0; k < star.count; ++k) {
    const DVec3 a = star.a[k] - mid, b = star.b[k] - mid, c = star.c[k] - mid;
    t.old_volume6 += Dot(a, Cross(b, c));
    t.area2 += Norm(Cross(b - a, c - a));
    if (star.survives[k]) t.normal_sum += Cross(b, c);
  }
  return t;
}

}  // namespace

DVec3 OntoVolumePlane(const EdgeStar& star, const DVec3& p) {
  const DVec3 mid = 0.5 * (star.v + star.vd);
  const VolumeTerms t = VolumeTermsOf(star, mid);
  if (!t.defined()) return p;
  return p + ((t.old_volume6 - Dot(p - mid, t.normal_sum)) / Dot(t.normal_sum, t.normal_sum)) *
                 t.normal_sum;
}

DVec3 OptimalPosition(const EdgeStar& star) {
  // Coordinates relative to the edge's midpoint, where the answer is (small numbers, no
  // cancellation).
  const DVec3 mid = 0.5 * (star.v + star.vd);
  double q[3][3] = {};
  double r[3] = {0, 0, 0};
  for (int k = 0; k < star.count; ++k) {
    const DVec3 a = star.a[k] - mid, b = star.b[k] - mid, c = star.c[k] - mid;
    const DVec3 n = Cross(b - a, c - a);
    const double len = Norm(n);
    if (!(len > 0.0)) continue;
    const DVec3 u = (1.0 / len) * n;
    const double weight = 0.5 * len, d = Dot(u, a);
    const double uu[3] = {u.x, u.y, u.z};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) q[i][j] += weight * uu[i] * uu[j];
      r[i] += weight * d * uu[i];
    }
  }
  const VolumeTerms volume = VolumeTermsOf(star, mid);
  const double pull = 1e-3 * (q[0][0] + q[1][1] + q[2][2]) / 3.0;
  double m[4][4] = {}, rhs[4] = {r[0], r[1], r[2], volume.old_volume6}, x[4] = {0, 0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i][j] = q[i][j];
    m[i][i] += pull;
  }
  // Keeping the volume is one linear constraint (a Lagrange multiplier in the fourth row).
  const DVec3 ns = volume.normal_sum;
  const double row[3] = {ns.x, ns.y, ns.z};
  const bool constrained = volume.defined();
  for (int i = 0; i < 3 && constrained; ++i) m[i][3] = m[3][i] = row[i];
  if (!Solve(constrained ? 4 : 3, m, rhs, x)) return mid;
  return mid + DVec3{x[0], x[1], x[2]};
}

}  // namespace femsimp
