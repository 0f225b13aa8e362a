#include "engine/planar_overlap.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace femsimp {
namespace {

constexpr double kLeastShare = 1e-6;  // of the smaller face's area

// A corner of the clipped polygon: where it is, and its coordinates in the projection plane.
struct Corner {
  DVec3 p;
  double u, v;
};

bool NearPlane(const Triangle& of, const DVec3& normal, double length, const Triangle& t,
               double tolerance) {
  for (const DVec3& q : t.p)
    if (std::fabs(Dot(normal, q - of.p[0])) > tolerance * length) return false;
  return true;
}

}  // namespace

std::optional<PlanarOverlap> OverlapInPlane(const Triangle& a, const Triangle& b,
                                            double plane_tolerance) {
  // Most pairs tested are apart or cross: b off a's plane ends the test first.
  const DVec3 na = Cross(a.p[1] - a.p[0], a.p[2] - a.p[0]);
  const double la = Norm(na);  // twice a's area
  if (!(la > 0.0) || !NearPlane(a, na, la, b, plane_tolerance)) return std::nullopt;
  const DVec3 nb = Cross(b.p[1] - b.p[0], b.p[2] - b.p[0]);
  const double lb = Norm(nb);
  if (!(lb > 0.0) || !NearPlane(b, nb, lb, a, plane_tolerance)) return std::nullopt;
  // Project along a's largest normal component; a counter-clockwise there.
  const double ax = std::fabs(na.x), ay = std::fabs(na.y), az = std::fabs(na.z);
  const int drop = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
  const auto project = [drop](const DVec3& p) {
    return drop == 0 ? Corner{p, p.y, p.z} : drop == 1 ? Corner{p, p.z, p.x} : Corner{p, p.x, p.y};
  };
  Corner clip[3] = {project(a.p[0]), project(a.p[1]), project(a.p[2])};
  const auto cross2 = [](const Corner& o, const Corner& s, const Corner& t) {
    return (s.u - o.u) * (t.v - o.v) - (s.v - o.v) * (t.u - o.u);
  };
  if (cross2(clip[0], clip[1], clip[2]) < 0.0) std::swap(clip[1], clip[2]);
  // Sutherland-Hodgman: b clipped by a's three edges (a triangle clipped thrice keeps <= 6).
  Corner poly[9], next[9];
  int n = 3;
  for (int k = 0; k < 3; ++k) poly[k] = project(b.p[k]);
  for (int e = 0; e < 3 && n > 0; ++e) {
    const Corner& s = clip[e];
    const Corner& t = clip[(e + 1) % 3];
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Corner& p = poly[i];
      const Corner& q = poly[(i + 1) % n];
      const double dp = cross2(s, t, p), dq = cross2(s, t, q);
      if (dp >= 0.0) next[m++] = p;
      if ((dp >= 0.0) != (dq >= 0.0)) {
        const double w = dp / (dp - dq);
        next[m++] = {p.p + w * (q.p - p.p), p.u + w * (q.u - p.u), p.v + w * (q.v - p.v)};
      }
    }
    n = m;
    std::copy(next, next + n, poly);
  }
  if (n < 3) return std::nullopt;
  // Area-weighted centroid of the fan from the first corner; the projected area scaled back.
  double twice_projected = 0.0;
  DVec3 weighted{0, 0, 0};
  for (int i = 1; i + 1 < n; ++i) {
    const double w = cross2(poly[0], poly[i], poly[i + 1]);
    twice_projected += w;
    weighted += (w / 3.0) * (poly[0].p + poly[i].p + poly[i + 1].p);
  }
  const double normal_share = (drop == 0 ? ax : drop == 1 ? ay : az) / la;
  const double area = 0.5 * std::fabs(twice_projected) / normal_share;  // b may wind either way
  if (!(area > kLeastShare * 0.5 * std::min(la, lb))) return std::nullopt;
  return PlanarOverlap{area, (1.0 / twice_projected) * weighted};
}

}  // namespace femsimp
