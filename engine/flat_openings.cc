#include "engine/flat_openings.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "absl/container/btree_map.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "engine/crossings.h"
#include "engine/facet_box_grid.h"
#include "engine/least_area_fill.h"
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

  FlatFills Fill(const std::vector<OpeningLoop>& loops) const {
    const size_t n = loops.size();
    // Each loop as it goes into its plane's fill (its notches cut off by their chords), and the
    // notches' facets.
    std::vector<std::vector<uint32_t>> ring(n), notch(n), notch_origin(n);
    std::vector<Point> normal(n), centre(n);
    std::vector<bool> planar(n);
    absl::btree_map<uint32_t, std::string> open;  // surface -> why it stays open
    const auto plane = [&](size_t i) {
      const std::vector<Point> p = Corners(ring[i]);
      normal[i] = NewellNormal(p.data(), p.size());
      centre[i] = {};
      for (const Point& q : p)
        for (int k = 0; k < 3; ++k) centre[i][k] += q[k] / double(p.size());
      planar[i] = std::all_of(p.begin(), p.end(), [&](const Point& q) {
        return Off(q, normal[i], centre[i]) <= tolerance_;
      });
    };
    for (size_t i = 0; i < n; ++i) {
      ring[i] = loops[i].vertices;
      plane(i);
      if (planar[i] || loops[i].small) continue;
      if (std::optional<Notched> split = SplitNotches(loops[i].vertices)) {
        ring[i] = std::move(split->ring);
        notch[i] = std::move(split->facets);
        notch_origin[i] = std::move(split->origins);
        plane(i);
      }
      if (!planar[i])
        open.try_emplace(
            loops[i].surface,
            absl::StrCat("the loop from vertex ", loops[i].vertices[0], " is not in one plane"));
    }
    std::vector<bool> grouped(n, false);
    std::vector<FlatFill> fills;
    std::vector<uint32_t> filled;  // the facets of the fills made so far
    for (size_t seed = 0; seed < n; ++seed) {
      if (loops[seed].small || grouped[seed] || !planar[seed]) continue;
      FlatFill fill;
      for (size_t i = 0; i < n; ++i) {
        // Its centre first: most loops of a part lie in other planes.
        if (grouped[i] || !planar[i] || Off(centre[i], normal[seed], centre[seed]) > tolerance_)
          continue;
        const std::vector<Point> p = Corners(ring[i]);
        if (std::all_of(p.begin(), p.end(), [&](const Point& q) {
              return Off(q, normal[seed], centre[seed]) <= tolerance_;
            })) {
          grouped[i] = true;
          fill.loops.push_back(i);
        }
      }
      if (std::string why = FillGroup(ring, notch, notch_origin, normal[seed], filled, &fill);
          !why.empty()) {
        for (size_t i : fill.loops) open.try_emplace(loops[i].surface, why);
        continue;
      }
      for (size_t i : fill.loops) fill.loop_edges += loops[i].vertices.size();
      filled.insert(filled.end(), fill.facets.begin(), fill.facets.end());
      fills.push_back(std::move(fill));
    }
    // A fill that closes a surface left open would not close it: dropped, and every surface it
    // meets stays open with it, until none is left to drop.
    for (bool dropped = true; dropped;) {
      dropped = false;
      for (size_t f = 0; f < fills.size(); ++f) {
        const auto meets_open = [&](size_t i) { return open.contains(loops[i].surface); };
        const auto it = std::find_if(fills[f].loops.begin(), fills[f].loops.end(), meets_open);
        if (it == fills[f].loops.end()) continue;
        const std::string why = absl::StrCat(
            "its loops' plane holds a loop of a surface left open: ", open.at(loops[*it].surface));
        for (size_t i : fills[f].loops) open.try_emplace(loops[i].surface, why);
        fills.erase(fills.begin() + f);
        dropped = true;
        break;
      }
    }
    FlatFills result{std::move(fills), {}};
    for (auto& [surface, why] : open) result.open.emplace_back(surface, std::move(why));
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
  double Area(const uint32_t* t) const {
    const Point a = Pos(t[0]), b = Pos(t[1]), c = Pos(t[2]);
    const Point e = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const Point g = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Point x = {e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2],
                     e[0] * g[1] - e[1] * g[0]};
    return 0.5 * std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
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

  // A loop off its plane only at a few corners, in runs (a facet dropped beside a dropped flat
  // face: its corner off the face's plane): the loop with each run cut off by the chord between
  // its neighbours, in one plane, and the facets that close each notch (the least-area
  // triangulation of the run and its chord, turned against the facets along it). Nullopt where
  // no more than kMaxNotchCorners corners leave the rest in one plane, a run is longer than 4,
  // a chord is an edge the surface has, or a notch has no allowed triangulation.
  struct Notched {
    std::vector<uint32_t> ring, facets;
    std::vector<uint32_t> origins;  // per facet: the facet along its notch's first edge
  };
  std::optional<Notched> SplitNotches(const std::vector<uint32_t>& loop) const {
    constexpr size_t kMaxNotchCorners = 6, kMaxRun = 4;
    const size_t n = loop.size();
    const std::vector<Point> p = Corners(loop);
    std::vector<bool> off(n, false);
    for (size_t removed = 0;; ++removed) {  // the farthest corner off the others' plane, in turn
      std::vector<Point> kept;
      for (size_t i = 0; i < n; ++i)
        if (!off[i]) kept.push_back(p[i]);
      if (kept.size() < 3) return std::nullopt;
      const Point normal = NewellNormal(kept.data(), kept.size());
      Point centre{};
      for (const Point& q : kept)
        for (int k = 0; k < 3; ++k) centre[k] += q[k] / double(kept.size());
      size_t farthest = n;
      double distance = tolerance_;
      for (size_t i = 0; i < n; ++i)
        if (!off[i] && Off(p[i], normal, centre) > distance) {
          distance = Off(p[i], normal, centre);
          farthest = i;
        }
      if (farthest == n) break;
      if (removed == kMaxNotchCorners) return std::nullopt;
      off[farthest] = true;
    }
    const size_t first = std::find(off.begin(), off.end(), false) - off.begin();
    Notched out;
    for (size_t t = 0; t < n; ++t) {
      const size_t i = (first + t) % n;
      if (!off[i]) {
        out.ring.push_back(loop[i]);
        continue;
      }
      if (off[(i + n - 1) % n]) continue;  // inside a run: taken with its start
      std::vector<uint32_t> q = {loop[(i + n - 1) % n]};
      size_t j = i;
      for (; off[j]; j = (j + 1) % n) q.push_back(loop[j]);
      q.push_back(loop[j]);
      if (q.size() > kMaxRun + 2 || Uses(q.front(), q.back()) > 0) return std::nullopt;
      const LeastAreaFill least = LeastAreaTriangulation(
          q.size(),
          [&](size_t a, size_t k, size_t b) {
            const float* x[3] = {&positions_[3 * size_t{q[a]}], &positions_[3 * size_t{q[k]}],
                                 &positions_[3 * size_t{q[b]}]};
            return !((k > a + 1 && Uses(q[a], q[k]) > 0) || (b > k + 1 && Uses(q[k], q[b]) > 0) ||
                     IsZeroArea(x[0], x[1], x[2]));
          },
          [&](size_t a, size_t k, size_t b) {
            const uint32_t t3[3] = {q[a], q[k], q[b]};
            return Area(t3);
          });
      if (least.triangles.empty()) return std::nullopt;
      size_t along = 0, against = 0;  // the run's edges, as their facets run them
      for (size_t e = 0; e + 1 < q.size(); ++e) {
        along += facet_along_.contains(Directed(q[e], q[e + 1]));
        against += facet_along_.contains(Directed(q[e + 1], q[e]));
      }
      auto origin = facet_along_.find(Directed(q[0], q[1]));
      if (origin == facet_along_.end()) origin = facet_along_.find(Directed(q[1], q[0]));
      if (origin == facet_along_.end()) return std::nullopt;
      out.origins.insert(out.origins.end(), least.triangles.size(), origin->second);
      for (const auto& [a, k, b] : least.triangles)
        if (along >= against) {
          out.facets.insert(out.facets.end(), {q[b], q[k], q[a]});
        } else {
          out.facets.insert(out.facets.end(), {q[a], q[k], q[b]});
        }
    }
    return out;
  }

  // Fills one plane's loops (`ring`; `notch`: their notches' facets, `notch_origin` the facet
  // each comes beside) into `fill` (`filled`: the facets of the fills made before); "" or why not.
  std::string FillGroup(const std::vector<std::vector<uint32_t>>& ring,
                        const std::vector<std::vector<uint32_t>>& notch,
                        const std::vector<std::vector<uint32_t>>& notch_origin, const Point& normal,
                        const std::vector<uint32_t>& filled, FlatFill* fill) const {
    std::vector<std::vector<Point>> corners;
    std::vector<uint32_t> ids;
    for (size_t i : fill->loops) {
      corners.push_back(Corners(ring[i]));
      ids.insert(ids.end(), ring[i].begin(), ring[i].end());
    }
    const std::string where =
        absl::StrCat("the loops in the plane of the one from vertex ", ring[fill->loops[0]][0]);
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
      fill->area += Area(v);
      fill->facets.insert(fill->facets.end(), v, v + 3);
    }
    for (size_t i : fill->loops) {
      const std::vector<uint32_t>& loop = ring[i];
      for (size_t j = 0; j < loop.size(); ++j) {
        const uint32_t a = loop[j], b = loop[(j + 1) % loop.size()];
        auto it = facet_along_.find(Directed(a, b));
        if (it == facet_along_.end()) it = facet_along_.find(Directed(b, a));
        if (it == facet_along_.end()) continue;  // a notch's chord
        ++fill->rim_edges;
        fill->rim_facets.push_back(it->second);
        bool flush = true;
        for (int c = 0; c < 3; ++c)
          flush = flush &&
                  Off(Pos(facets_[3 * size_t{it->second} + c]), normal, Pos(loop[0])) <= tolerance_;
        fill->flush_edges += flush;
      }
    }
    for (size_t i : fill->loops) {
      for (size_t c = 0; c < notch[i].size(); c += 3) {
        const uint32_t* t = &notch[i][c];
        fill->area += Area(t);
        for (int k = 0; k < 3; ++k) {
          const Point q = Pos(t[k]);
          for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], q[d]);
            hi[d] = std::max(hi[d], q[d]);
          }
        }
      }
      fill->facets.insert(fill->facets.end(), notch[i].begin(), notch[i].end());
      fill->notch_origins.insert(fill->notch_origins.end(), notch_origin[i].begin(),
                                 notch_origin[i].end());
    }
    std::sort(fill->rim_facets.begin(), fill->rim_facets.end());
    fill->rim_facets.erase(std::unique(fill->rim_facets.begin(), fill->rim_facets.end()),
                           fill->rim_facets.end());
    if (std::string why = Crossing(*fill, filled, lo, hi); !why.empty())
      return absl::StrCat(where, ": ", why);
    return "";
  }

  // Whether the fill's facets cross, overlap or fold onto the surface's or the earlier fills'
  // (`filled`) within their box.
  std::string Crossing(const FlatFill& fill, const std::vector<uint32_t>& filled, Point lo,
                       Point hi) const {
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
    const FacetBox box{lo, hi};
    // The surface's facets through the grid of their boxes (made once, at the first fill: a
    // read of every facet per fill made many openings on a large mesh quadratic), in their
    // order; then the earlier fills' (a few).
    if (!grid_) {
      std::vector<FacetBox> boxes(facets_.size() / 3);
      for (size_t f = 0; f < boxes.size(); ++f) boxes[f] = FacetBoxOf(positions_, &facets_[3 * f]);
      grid_.emplace(std::move(boxes));
    }
    std::vector<uint32_t> meeting;
    grid_->ForEachMeeting(box, [&](uint32_t f) { meeting.push_back(f); });
    std::sort(meeting.begin(), meeting.end());
    for (uint32_t f : meeting) add(&facets_[3 * size_t{f}]);
    for (size_t f = 0; f < filled.size(); f += 3)
      if (FacetBoxOf(positions_, &filled[f]).Meets(box)) add(&filled[f]);
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
  mutable std::optional<FacetBoxGrid> grid_;             // facets_'s boxes, once a fill is checked
  absl::flat_hash_map<uint64_t, uint32_t> facet_along_;  // directed edge -> first facet on it
  absl::flat_hash_map<uint64_t, uint32_t> uses_;         // undirected edge -> facets on it
};

}  // namespace

FlatFills FillFlatOpenings(const std::vector<float>& positions, const std::vector<uint32_t>& facets,
                           const std::vector<OpeningLoop>& loops, double plane_tolerance) {
  if (loops.empty()) return {};
  return Filler(positions, facets, plane_tolerance).Fill(loops);
}

}  // namespace femsimp
