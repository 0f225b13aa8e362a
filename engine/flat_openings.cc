#include "engine/flat_openings.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/crossings.h"
#include "engine/mesh_checks.h"
#include "engine/plane_fill.h"
#include "engine/raw_mesh.h"

namespace femsimp {
namespace {

using Point = std::array<double, 3>;

uint64_t Directed(uint32_t a, uint32_t b) { return uint64_t{a} << 32 | b; }

class Filler {
 public:
  Filler(const std::vector<float>& positions, const std::vector<uint32_t>& facets,
         double plane_tolerance)
      : positions_(positions), facets_(facets), tolerance_(plane_tolerance) {
    for (size_t c = 0; c < facets.size(); ++c) {
      const uint32_t a = facets[c], b = facets[c % 3 == 2 ? c - 2 : c + 1];
      facet_along_.try_emplace(Directed(a, b), static_cast<uint32_t>(c / 3));
      ++uses_[Directed(std::min(a, b), std::max(a, b))];
    }
  }

  FlatFillResult Fill(const OpeningSet& set) const {
    FlatFillResult result;
    const size_t n = set.loops.size();
    std::vector<Point> normal(n), centre(n);
    std::vector<bool> planar(n);
    for (size_t i = 0; i < n; ++i) {
      const std::vector<Point> p = Corners(set.loops[i]);
      normal[i] = NewellNormal(p.data(), p.size());
      for (const Point& q : p)
        for (int k = 0; k < 3; ++k) centre[i][k] += q[k] / double(p.size());
      planar[i] = std::all_of(p.begin(), p.end(), [&](const Point& q) {
        return Off(q, normal[i], centre[i]) <= tolerance_;
      });
      if (!planar[i] && !set.small[i]) {
        result.why_not =
            absl::StrCat("the loop from vertex ", set.loops[i][0], " is not in one plane");
        return result;
      }
    }
    std::vector<bool> grouped(n, false);
    for (size_t seed = 0; seed < n; ++seed) {
      if (set.small[seed] || grouped[seed]) continue;
      FlatFill fill;
      for (size_t i = 0; i < n; ++i) {
        if (grouped[i] || !planar[i]) continue;
        const std::vector<Point> p = Corners(set.loops[i]);
        if (std::all_of(p.begin(), p.end(), [&](const Point& q) {
              return Off(q, normal[seed], centre[seed]) <= tolerance_;
            })) {
          grouped[i] = true;
          fill.loops.push_back(i);
        }
      }
      if (std::string why = FillGroup(set, normal[seed], &fill); !why.empty()) {
        result.why_not = std::move(why);
        result.fills.clear();
        return result;
      }
      result.fills.push_back(std::move(fill));
    }
    return result;
  }

 private:
  Point Pos(uint32_t v) const {
    const float* p = &positions_[3 * size_t{v}];
    return {p[0], p[1], p[2]};
  }
  std::vector<Point> Corners(const std::vector<uint32_t>& loop) const {
    std::vector<Point> p;
    p.reserve(loop.size());
    for (uint32_t v : loop) p.push_back(Pos(v));
    return p;
  }
  static double Off(const Point& q, const Point& normal, const Point& centre) {
    const double l =
        std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(l > 0)) return HUGE_VAL;
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (q[k] - centre[k]) * normal[k];
    return std::fabs(d) / l;
  }
  uint32_t Uses(uint32_t a, uint32_t b) const {
    const auto it = uses_.find(Directed(std::min(a, b), std::max(a, b)));
    return it == uses_.end() ? 0 : it->second;
  }

  // Fills one plane's loops into `fill`; "" or why not.
  std::string FillGroup(const OpeningSet& set, const Point& normal, FlatFill* fill) const {
    std::vector<std::vector<Point>> corners;
    std::vector<uint32_t> ids;
    for (size_t i : fill->loops) {
      corners.push_back(Corners(set.loops[i]));
      ids.insert(ids.end(), set.loops[i].begin(), set.loops[i].end());
    }
    const std::string where = absl::StrCat("the loops in the plane of the one from vertex ",
                                           set.loops[fill->loops[0]][0]);
    absl::StatusOr<std::vector<std::array<uint32_t, 3>>> triangles =
        FillPlaneRegion(corners, normal);
    if (!triangles.ok())
      return absl::StrCat(where, " bound no region: ", triangles.status().message());
    // Turned against the facets along the loops (as a surface's facets run an edge both ways).
    size_t along = 0, against = 0;
    for (const auto& t : *triangles)
      for (int c = 0; c < 3; ++c) {
        const uint32_t a = ids[t[c]], b = ids[t[(c + 1) % 3]];
        along += facet_along_.contains(Directed(a, b));
        against += facet_along_.contains(Directed(b, a));
      }
    const bool turn = along > against;
    Point lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const auto& t : *triangles) {
      uint32_t v[3] = {ids[t[0]], ids[t[1]], ids[t[2]]};
      if (turn) std::swap(v[1], v[2]);
      for (int c = 0; c < 3; ++c) {
        const uint32_t a = v[c], b = v[(c + 1) % 3];
        const bool rim =
            facet_along_.contains(Directed(a, b)) || facet_along_.contains(Directed(b, a));
        if (!rim && Uses(a, b) > 0)
          return absl::StrCat(where, ": a fill would add an edge the surface has (vertices ", a,
                              " and ", b, ")");
        const Point p = Pos(a);
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], p[k]);
          hi[k] = std::max(hi[k], p[k]);
        }
      }
      const float* p[3] = {&positions_[3 * size_t{v[0]}], &positions_[3 * size_t{v[1]}],
                           &positions_[3 * size_t{v[2]}]};
      if (IsZeroArea(p[0], p[1], p[2]))
        return absl::StrCat(where, ": a fill would make a facet of no area (vertices ", v[0], ", ",
                            v[1], ", ", v[2], ")");
      const Point e = {double{p[1][0]} - p[0][0], double{p[1][1]} - p[0][1],
                       double{p[1][2]} - p[0][2]};
      const Point g = {double{p[2][0]} - p[0][0], double{p[2][1]} - p[0][1],
                       double{p[2][2]} - p[0][2]};
      const Point x = {e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2],
                       e[0] * g[1] - e[1] * g[0]};
      fill->area += 0.5 * std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      fill->facets.insert(fill->facets.end(), v, v + 3);
    }
    for (size_t i : fill->loops) {
      const std::vector<uint32_t>& loop = set.loops[i];
      for (size_t j = 0; j < loop.size(); ++j) {
        const uint32_t a = loop[j], b = loop[(j + 1) % loop.size()];
        auto it = facet_along_.find(Directed(a, b));
        if (it == facet_along_.end()) it = facet_along_.find(Directed(b, a));
        ++fill->rim_edges;
        if (it == facet_along_.end()) continue;
        fill->rim_facets.push_back(it->second);
        bool flush = true;
        for (int c = 0; c < 3; ++c)
          flush = flush &&
                  Off(Pos(facets_[3 * size_t{it->second} + c]), normal, Pos(loop[0])) <= tolerance_;
        fill->flush_edges += flush;
      }
    }
    std::sort(fill->rim_facets.begin(), fill->rim_facets.end());
    fill->rim_facets.erase(std::unique(fill->rim_facets.begin(), fill->rim_facets.end()),
                           fill->rim_facets.end());
    if (std::string why = Crossing(*fill, lo, hi); !why.empty())
      return absl::StrCat(where, ": ", why);
    return "";
  }

  // Whether the fill's facets cross, overlap or fold onto the surface's within their box.
  std::string Crossing(const FlatFill& fill, Point lo, Point hi) const {
    for (int k = 0; k < 3; ++k) {
      lo[k] -= tolerance_;
      hi[k] += tolerance_;
    }
    RawMesh near;
    absl::flat_hash_map<uint32_t, uint32_t> index;
    const auto add = [&](const uint32_t* t) {
      for (int c = 0; c < 3; ++c) {
        const auto [it, fresh] = index.try_emplace(t[c], static_cast<uint32_t>(index.size()));
        if (fresh)
          near.positions.insert(near.positions.end(), &positions_[3 * size_t{t[c]}],
                                &positions_[3 * size_t{t[c]}] + 3);
        near.triangles.push_back(it->second);
      }
    };
    for (size_t f = 0; f < facets_.size(); f += 3) {
      bool meets = true;
      for (int k = 0; k < 3 && meets; ++k) {
        double a = HUGE_VAL, b = -HUGE_VAL;
        for (int c = 0; c < 3; ++c) {
          a = std::min(a, double{positions_[3 * size_t{facets_[f + c]} + k]});
          b = std::max(b, double{positions_[3 * size_t{facets_[f + c]} + k]});
        }
        meets = a <= hi[k] && b >= lo[k];
      }
      if (meets) add(&facets_[f]);
    }
    const SoupCrossings before = FindCrossings(near);
    for (size_t f = 0; f < fill.facets.size(); f += 3) add(&fill.facets[f]);
    const SoupCrossings after = FindCrossings(near);
    if (after.pairs > before.pairs) return "a fill would cross the surface";
    if (after.overlaps.pairs > before.overlaps.pairs) return "a fill would overlap the surface";
    if (after.folds.pairs > before.folds.pairs) return "a fill would fold onto the surface";
    return "";
  }

  const std::vector<float>& positions_;
  const std::vector<uint32_t>& facets_;
  const double tolerance_;
  absl::flat_hash_map<uint64_t, uint32_t> facet_along_;  // directed edge -> first facet on it
  absl::flat_hash_map<uint64_t, uint32_t> uses_;         // undirected edge -> facets on it
};

}  // namespace

std::vector<FlatFillResult> FillFlatOpenings(const std::vector<float>& positions,
                                             const std::vector<uint32_t>& facets,
                                             const std::vector<OpeningSet>& sets,
                                             double plane_tolerance) {
  std::vector<FlatFillResult> results;
  if (sets.empty()) return results;
  const Filler filler(positions, facets, plane_tolerance);
  for (const OpeningSet& set : sets) results.push_back(filler.Fill(set));
  return results;
}

}  // namespace femsimp
