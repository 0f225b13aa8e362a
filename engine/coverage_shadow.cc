// The shadow certificate of the measured check's (b) (engine/coverage.h; docs/FIDELITY.md § 1).
// Seen along the normal n of a part R of a new face, take the input triangles that lie within
// the tolerance of R's plane and face the same way (counter-clockwise seen along n), connected
// across input edges: S. Where S's shadow covers R's, every point x of R has a point y of S
// straight below or above it, |x - y| = |n.(y - x)| <= the tolerance. The shadow of S can end
// only at an edge with one side in S (across a shared edge the two triangles lie on either
// side; around a vertex with every edge shared, the fan winds at least once), so it covers R's
// when R's centre is under a triangle of S and no such edge meets R's shadow.
#include <algorithm>
#include <cmath>

#include "engine/coverage.h"

namespace femsimp {
namespace {

using Flat = CoveragePlan::Point2;

// Twice the signed area of (a, b, p): positive when p is left of a -> b.
double Turn(const Flat& a, const Flat& b, const Flat& p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

double Length(const Flat& a, const Flat& b) {
  return std::sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
}

// False where the segment ab misses the inside of the counter-clockwise triangle r: a side of
// r, or ab's own line, has them on its two sides (touching allowed).
bool MeetsInside(const Flat& a, const Flat& b, const Flat r[3]) {
  for (int i = 0; i < 3; ++i) {
    const Flat& p = r[i];
    const Flat& q = r[(i + 1) % 3];
    if (Turn(p, q, a) <= 0 && Turn(p, q, b) <= 0) return false;
  }
  bool left = true, right = true;
  for (int i = 0; i < 3; ++i) {
    const double t = Turn(a, b, r[i]);
    left = left && t >= 0;
    right = right && t <= 0;
  }
  return !(left || right);
}

// The counter-clockwise triangle r with its sides moved inwards by s, into `inset`: how far a
// point of r may be from it (at most), or negative when nothing is left of r.
double Inset(const Flat r[3], double s, Flat inset[3]) {
  Flat normal[3];  // inward, of side i -> i + 1
  for (int i = 0; i < 3; ++i) {
    const Flat& p = r[i];
    const Flat& q = r[(i + 1) % 3];
    const double length = Length(p, q);
    if (!(length > 0)) return -1;
    normal[i] = {-(q.y - p.y) / length, (q.x - p.x) / length};
  }
  double farthest = 0;
  for (int i = 0; i < 3; ++i) {
    const Flat& a = normal[(i + 2) % 3];  // the sides meeting at corner i
    const Flat& b = normal[i];
    const double sum = 1 + a.x * b.x + a.y * b.y;
    if (!(sum > 1e-6)) return -1;  // a needle: its tip moves too far
    const Flat shift{s * (a.x + b.x) / sum, s * (a.y + b.y) / sum};
    inset[i] = {r[i].x + shift.x, r[i].y + shift.y};
    farthest = std::max(farthest, std::sqrt(shift.x * shift.x + shift.y * shift.y));
  }
  return Turn(inset[0], inset[1], inset[2]) > 0 ? farthest : -1;
}

}  // namespace

double ClippedHeight(const CoveragePlan::Point2 xy[3], const double h[3],
                     const CoveragePlan::Point2 r[3]) {
  constexpr int kMax = 9;  // a triangle cut by three lines keeps at most six corners
  Flat poly[kMax], next[kMax];
  double height[kMax], next_height[kMax];
  int count = 3;
  for (int k = 0; k < 3; ++k) {
    poly[k] = xy[k];
    height[k] = h[k];
  }
  for (int i = 0; i < 3 && count > 0; ++i) {
    const Flat& a = r[i];
    const Flat& b = r[(i + 1) % 3];
    int kept = 0;
    for (int k = 0; k < count; ++k) {
      const int l = (k + 1) % count;
      const double sk = Turn(a, b, poly[k]), sl = Turn(a, b, poly[l]);
      if (sk >= 0) {
        next[kept] = poly[k];
        next_height[kept++] = height[k];
      }
      if ((sk >= 0) != (sl >= 0)) {
        const double t = sk / (sk - sl);
        next[kept] = {poly[k].x + t * (poly[l].x - poly[k].x),
                      poly[k].y + t * (poly[l].y - poly[k].y)};
        next_height[kept++] = height[k] + t * (height[l] - height[k]);
      }
    }
    count = kept;
    std::copy(next, next + count, poly);
    std::copy(next_height, next_height + count, height);
  }
  if (count == 0) return -1;
  double highest = 0;
  for (int k = 0; k < count; ++k) highest = std::max(highest, std::fabs(height[k]));
  return highest;
}

double Coverage::WithinShadow(const DVec3* c, std::span<const uint32_t> seeds, CoveragePlan* plan,
                              uint64_t* work) const {
  const DVec3 e1 = c[1] - c[0], e2 = c[2] - c[0];
  const DVec3 normal = Cross(e1, e2);
  const double area2 = Norm(normal), length = Norm(e1);
  if (!(area2 > 0) || !(length > 0)) return -1;
  const DVec3 n = (1.0 / area2) * normal, u = (1.0 / length) * e1, w = Cross(n, u);
  const auto flat = [&](const DVec3& q) {
    const DVec3 d = q - c[0];
    return Flat{Dot(u, d), Dot(w, d)};
  };
  const Flat r[3] = {{0, 0}, flat(c[1]), flat(c[2])};
  // What rounding may move a point by, here: far below the tolerance's own margin.
  const double magnitude =
      std::max({std::fabs(c[0].x), std::fabs(c[0].y), std::fabs(c[0].z), length, Norm(e2)});
  const double slack = 1e-12 * magnitude;
  const double height_limit = plan->limit - slack;
  const Flat lo{std::min({r[0].x, r[1].x, r[2].x}) - slack,
                std::min({r[0].y, r[1].y, r[2].y}) - slack};
  const Flat hi{std::max({r[0].x, r[1].x, r[2].x}) + slack,
                std::max({r[0].y, r[1].y, r[2].y}) + slack};
  const Flat centre{(r[0].x + r[1].x + r[2].x) / 3, (r[0].y + r[1].y + r[2].y) / 3};
  // An edge of S may run along R's sides (a rim edge that is an input edge): only R's inside,
  // moved in by the slack, must be clear of them; the rest of R is that close to it.
  Flat inset[3];
  const double rim = Inset(r, slack, inset);
  if (rim < 0) return -1;
  // R's sides moved out by the slack: a triangle clipped to it keeps all of its part over R
  // whatever the rounding of the clip.
  Flat outset[3];
  if (Inset(r, -slack, outset) < 0) return -1;

  std::vector<CoveragePlan::Shade>& shade = plan->shade;
  std::vector<uint32_t>& slot = plan->shade_slot;
  if (slot.size() != whole_.size()) slot.assign(whole_.size(), kNone);
  shade.clear();
  // Judges triangle t (not yet in `shade`) and returns its index there. The tests are ordered
  // cheapest and most selective first: only a member's height is read later, so a triangle
  // whose shadow misses R's box costs its shadow only.
  const auto judge = [&](uint32_t t) -> uint32_t {
    CoveragePlan::Shade s{t, false, 0, {}};
    const Vec3* p = &input_[3 * size_t{t}];
    DVec3 d[3];
    for (int k = 0; k < 3; ++k) {
      d[k] = ToD(p[k]) - c[0];
      s.xy[k] = Flat{Dot(u, d[k]), Dot(w, d[k])};
    }
    // A triangle whose shadow misses R's box adds nothing (its edges are tested).
    bool ok = std::max({s.xy[0].x, s.xy[1].x, s.xy[2].x}) >= lo.x &&
              std::min({s.xy[0].x, s.xy[1].x, s.xy[2].x}) <= hi.x &&
              std::max({s.xy[0].y, s.xy[1].y, s.xy[2].y}) >= lo.y &&
              std::min({s.xy[0].y, s.xy[1].y, s.xy[2].y}) <= hi.y;
    if (ok) {
      // Facing R's way by more than rounding: twice the area above the slack times the
      // perimeter, which the sum of the sides' |dx| + |dy| bounds from above (the square roots
      // only near it).
      const double turn = Turn(s.xy[0], s.xy[1], s.xy[2]);
      double manhattan = 0;
      for (int k = 0; k < 3; ++k)
        manhattan +=
            std::fabs(s.xy[(k + 1) % 3].x - s.xy[k].x) + std::fabs(s.xy[(k + 1) % 3].y - s.xy[k].y);
      ok = turn > slack * manhattan ||
           (turn > 0 && turn > slack * (Length(s.xy[0], s.xy[1]) + Length(s.xy[1], s.xy[2]) +
                                        Length(s.xy[2], s.xy[0])));
    }
    if (ok) {
      double heights[3];
      for (int k = 0; k < 3; ++k) {
        heights[k] = Dot(n, d[k]);
        s.height = std::max(s.height, std::fabs(heights[k]));
      }
      if (s.height > height_limit) {
        // Only its part over R must lie in the slab (the points of S the certificate uses are
        // under R): a triangle that crosses R's border may rise beyond it outside. The clipped
        // heights are interpolations: a relative margin covers their rounding.
        const double over_r = ClippedHeight(s.xy, heights, outset);
        ok = over_r >= 0 && over_r + 1e-12 * s.height <= height_limit;
        if (ok) s.height = over_r + 1e-12 * s.height;
      }
    }
    s.member = ok;
    const uint32_t at = static_cast<uint32_t>(shade.size());
    slot[t] = at;
    shade.push_back(s);
    return at;
  };
  // The index of triangle t in `shade`, judged the first time it is seen.
  const auto visit = [&](uint32_t t) -> uint32_t {
    const uint32_t at = slot[t];
    return at != kNone ? at : judge(t);
  };

  // S grows from the seeds across shared edges; an edge with one side in S ends its shadow.
  const auto walk = [&]() -> double {
    for (uint32_t i : seeds) visit(plan->witnesses[i].triangle);
    bool centre_covered = false;
    double reach = 0;
    for (size_t i = 0; i < shade.size(); ++i) {
      if (shade.size() > kMaxShade) return -1;
      if (!shade[i].member) continue;
      const uint32_t t = shade[i].triangle;
      const Flat xy[3] = {shade[i].xy[0], shade[i].xy[1], shade[i].xy[2]};
      reach = std::max(reach, shade[i].height);
      if (!centre_covered) {
        bool inside = true;
        // On an edge or a corner counts (S's triangles are closed): with every edge of S that
        // could end its shadow outside R's inside, R's centre under S puts all of R under it.
        for (int k = 0; k < 3 && inside; ++k)
          inside = Turn(xy[k], xy[(k + 1) % 3], centre) >= -slack * Length(xy[k], xy[(k + 1) % 3]);
        centre_covered = inside;
      }
      // Half-edge 3t + e runs from corner e + 2 to corner e (mod 3).
      for (int e = 0; e < 3; ++e) {
        const uint32_t across = across_[3 * size_t{t} + e];
        if (across != kNone && shade[visit(across)].member) continue;
        if (MeetsInside(xy[(e + 2) % 3], xy[e], inset)) return -1;
      }
    }
    if (!centre_covered) return -1;
    reach += rim + slack;
    return reach <= plan->limit ? reach : -1;
  };
  const double reach = walk();
  for (const CoveragePlan::Shade& s : shade) slot[s.triangle] = kNone;
  *work += shade.size() / 16;
  return reach;
}

}  // namespace femsimp
