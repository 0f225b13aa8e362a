#include "engine/deviation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/vec.h"

namespace femsimp {
namespace {

struct P2 {
  double x, y;
};
P2 Sub2(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
double Cross2(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
double Orient(P2 a, P2 b, P2 c) { return Cross2(Sub2(b, a), Sub2(c, a)); }
double AngleAt(P2 a, P2 b, P2 c) {  // angle b-a-c
  const P2 u = Sub2(b, a), w = Sub2(c, a);
  return std::atan2(std::fabs(Cross2(u, w)), u.x * w.x + u.y * w.y);
}

// Interiors of two counter-clockwise triangles intersect (touching within eps counts, so the
// test errs towards overlap: a larger, still valid bound).
bool Overlap(const P2* t, const P2* u, double eps) {
  const P2* tri[2] = {t, u};
  for (int s = 0; s < 2; ++s) {
    const P2* a = tri[s];
    const P2* b = tri[1 - s];
    for (int e = 0; e < 3; ++e) {
      const P2 p = a[e], q = a[(e + 1) % 3];
      const P2 d = Sub2(q, p);
      const double len = std::sqrt(d.x * d.x + d.y * d.y);  // mesh coordinates: no overflow
      // b entirely on the outer (right) side of edge p -> q separates them.
      bool separated = true;
      for (int k = 0; k < 3 && separated; ++k) separated = Cross2(d, Sub2(b[k], p)) < -eps * len;
      if (separated) return false;
    }
  }
  return true;
}

// Barycentric coordinates of p in (a, b, c), given twice its signed area.
void Barycentric(P2 p, P2 a, P2 b, P2 c, double area2, double* l) {
  l[0] = Orient(p, b, c) / area2;
  l[1] = Orient(a, p, c) / area2;
  l[2] = 1.0 - l[0] - l[1];
}

}  // namespace

bool BoundDeviation(const Ring& ring, int target, int line_other, const float* old_error,
                    float* new_error, int* work) {
  const int n = ring.neighbours();
  const int nf = ring.faces;
  const DVec3 v = ToD(ring.center_pos);
  DVec3 p[kMaxRing + 1];
  for (int k = 0; k < n; ++k) p[k] = ToD(ring.pos[k]);
  if (ring.boundary && line_other < 0) return false;  // boundary vertices slide along it only

  // The layout plane: perpendicular to the fan's area-weighted normal.
  DVec3 normal{0, 0, 0};
  for (int f = 0; f < nf; ++f) normal += Cross(p[f] - v, p[(f + 1) % n] - v);
  const double nlen = Norm(normal);
  if (!(nlen > 0.0)) return false;
  normal = (1.0 / nlen) * normal;
  const DVec3 helper = std::fabs(normal.x) < 0.6 ? DVec3{1, 0, 0} : DVec3{0, 1, 0};
  DVec3 u = Cross(normal, helper);
  u = (1.0 / Norm(u)) * u;
  const DVec3 w = Cross(normal, u);
  P2 q[kMaxRing + 1];
  double scale = 0.0;
  for (int k = 0; k < n; ++k) {
    q[k] = {Dot(p[k] - v, u), Dot(p[k] - v, w)};
    scale = std::max(scale, std::sqrt(q[k].x * q[k].x + q[k].y * q[k].y));
  }
  const double eps_len = 1e-9 * scale, eps_area = 1e-12 * scale * scale;

  // Where V goes: itself, or its closest point on the new feature edge (line_other, target).
  DVec3 vp = v;
  if (line_other >= 0) {
    const DVec3 a = p[line_other], d = p[target] - p[line_other];
    const double s = Dot(v - a, d) / Dot(d, d);
    if (!(s > 1e-6 && s < 1.0 - 1e-6)) return false;  // V' would sit on a line vertex
    vp = a + s * d;
  }
  const P2 v2 = {Dot(vp - v, u), Dot(vp - v, w)};

  // Old layout: fan faces with V at V'. It must wind once around V' (half a turn on a
  // boundary, where V' lies on the straight new boundary edge).
  double angle_v = 0.0, angle_vd_old = 0.0;
  for (int f = 0; f < nf; ++f) {
    const int b = f, c = (f + 1) % n;
    if (!(Orient(v2, q[b], q[c]) > eps_area)) return false;
    angle_v += AngleAt(v2, q[b], q[c]);
    if (b == target) angle_vd_old += AngleAt(q[b], q[c], v2);
    if (c == target) angle_vd_old += AngleAt(q[c], v2, q[b]);
  }
  const double full = ring.boundary ? std::numbers::pi : 2.0 * std::numbers::pi;
  if (std::fabs(angle_v - full) > 1e-6) return false;

  // New layout: the surviving faces with Vd for V, tiling the same polygon from Vd.
  const P2 qd = q[target];
  bool survives[kMaxRing];
  double angle_vd_new = 0.0;
  for (int f = 0; f < nf; ++f) {
    const int b = f, c = (f + 1) % n;
    survives[f] = b != target && c != target;
    if (!survives[f]) continue;
    if (!(Orient(qd, q[b], q[c]) > eps_area)) return false;
    angle_vd_new += AngleAt(qd, q[b], q[c]);
  }
  if (std::fabs(angle_vd_new - angle_vd_old) > 1e-6) return false;

  // Displacement at V', on the new face(s) holding its position.
  double disp_v[kMaxRing];
  bool placed = false;
  for (int f = 0; f < nf; ++f) {
    disp_v[f] = -1.0;  // V' not on this face
    if (!survives[f]) continue;
    const int b = f, c = (f + 1) % n;
    double l[3];
    Barycentric(v2, qd, q[b], q[c], Orient(qd, q[b], q[c]), l);
    if (l[0] < -1e-9 || l[1] < -1e-9 || l[2] < -1e-9) continue;
    const DVec3 at = l[0] * p[target] + l[1] * p[b] + l[2] * p[c];
    disp_v[f] = Norm(at - v);
    placed = true;
  }
  if (!placed) return false;

  // Displacement where old spoke V' -> k crosses new spoke Vd -> j (negative: no crossing).
  const auto crossing = [&](int k, int j) {
    const P2 dk = Sub2(q[k], v2), dj = Sub2(q[j], qd);
    const double denom = Cross2(dk, dj);
    if (std::fabs(denom) <= 1e-15 * scale * scale) return -1.0;  // parallel: meet at ends only
    const P2 r = Sub2(qd, v2);
    const double s = Cross2(r, dj) / denom, t = Cross2(r, dk) / denom;
    if (s < -1e-9 || s > 1 + 1e-9 || t < -1e-9 || t > 1 + 1e-9) return -1.0;
    return Norm((v + s * (p[k] - v)) - (p[target] + t * (p[j] - p[target])));
  };

  // On each cell (old face f) x (new face g) of the overlay the displacement is affine, so its
  // length peaks at a cell corner: V', a link vertex (0) or a spoke crossing; the cell's points
  // moved at most e_f before. The new bound of g is the worst cell over the f it overlaps.
  struct Box {
    double lo_x, lo_y, hi_x, hi_y;
  };
  const auto box = [](P2 a, P2 b, P2 c) {
    return Box{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::max({a.x, b.x, c.x}),
               std::max({a.y, b.y, c.y})};
  };
  Box old_box[kMaxRing];
  for (int f = 0; f < nf; ++f) old_box[f] = box(v2, q[f], q[(f + 1) % n]);
  int tests = nf;
  for (int g = 0; g < nf; ++g) {
    if (!survives[g]) continue;
    const int g2 = (g + 1) % n;
    const P2 tg[3] = {qd, q[g], q[g2]};
    const Box gb = box(qd, q[g], q[g2]);
    double bound = 0.0;
    for (int f = 0; f < nf; ++f) {
      const int f2 = (f + 1) % n;
      const Box& fb = old_box[f];
      if (fb.lo_x > gb.hi_x + eps_len || gb.lo_x > fb.hi_x + eps_len ||
          fb.lo_y > gb.hi_y + eps_len || gb.lo_y > fb.hi_y + eps_len)
        continue;  // cannot overlap
      const P2 tf[3] = {v2, q[f], q[f2]};
      ++tests;
      if (!Overlap(tf, tg, eps_len)) continue;
      double worst = std::max(0.0, disp_v[g]);
      for (int k : {f, f2}) {
        if (k == target) continue;
        for (int j : {g, g2}) {
          if (j == target || j == k) continue;
          ++tests;
          worst = std::max(worst, crossing(k, j));
        }
      }
      bound = std::max(bound, double(old_error[f]) + worst);
    }
    // Round up: the float must not fall below the double bound.
    new_error[g] = std::nextafter(static_cast<float>(bound + eps_len), 1e30f);
  }
  *work = tests;
  return true;
}

}  // namespace femsimp
