#include "engine/crossing_repair.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_format.h"
#include "engine/crossings.h"
#include "engine/facet_box_grid.h"
#include "engine/least_area_fill.h"
#include "engine/mesh_checks.h"
#include "engine/plane_fill.h"
#include "engine/triangle_distance.h"
#include "engine/union_find.h"
#include "engine/vec.h"
#include "engine/worker_pool.h"

namespace femsimp {
namespace {

using Facet = std::array<uint32_t, 3>;

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t{a} << 32) | b;
}

// A patch planned for taking out: its facets (current indices) and what closes it.
struct Plan {
  std::vector<uint32_t> facets;
  std::vector<Facet> fill;
  std::vector<uint32_t> fill_origin;  // per fill facet: the mesh given's facet it takes after
  UncrossedPatch patch;
  std::string refused;  // why not, where not empty
};

class Uncrosser {
 public:
  Uncrosser(const RawMesh& mesh, int threads, CrossingScope scope)
      : mesh_(mesh), threads_(threads), scope_(scope) {}

  UncrossResult Run() {
    const size_t nf = mesh_.num_faces();
    facets_.resize(nf);
    origin_.resize(nf);
    for (uint32_t f = 0; f < nf; ++f) {
      facets_[f] = {mesh_.triangles[3 * f], mesh_.triangles[3 * f + 1], mesh_.triangles[3 * f + 2]};
      origin_[f] = f;
    }
    CrossingPairLists lists;
    if (threads_ > 1) pool_.emplace(threads_);
    const SoupCrossings found = FindCrossings(mesh_, {.lists = &lists,
                                                      .crossings_only = true,
                                                      .stop_after = kEnoughCrossingPairs,
                                                      .pool = pool()});
    InScope(lists.crossing);
    result_.pairs_before = lists.crossing.size();
    if (lists.crossing.empty()) return std::move(result_);
    if (found.cut_short) {  // a soup crossing itself everywhere: not vertices written wrongly
      const DVec3 at{found.at[0] - mesh_.origin[0], found.at[1] - mesh_.origin[1],
                     found.at[2] - mesh_.origin[2]};
      result_.left.push_back(
          {found.face_a,
           {at.x, at.y, at.z},
           absl::StrFormat("more than %u face pairs cross; left as they are: far more than "
                           "vertices written wrongly make (a soup of facets, or bodies exported "
                           "overlapping)",
                           kEnoughCrossingPairs)});
      result_.pairs_after = result_.pairs_before;
      return std::move(result_);
    }
    tolerance_ = ContactPlaneTolerance(mesh_);
    const CrossingPairLists given = lists;

    // One vertex taken out with its facets (a vertex written wrongly), or the vertices farthest
    // off their rings together, where that frees every crossing pair of a cluster; a second
    // round for what the first left (a cluster whose vertex lay in another's facets).
    for (int round = 0; round < 2 && !lists.crossing.empty(); ++round) {
      if (!TakeOutVertices(lists.crossing)) break;
      lists = CrossingPairLists();
      FindCrossings(Soup(facets_), {.lists = &lists, .crossings_only = true, .pool = pool()});
      InScope(lists.crossing);
    }
    result_.pairs_after = lists.crossing.size();
    if (result_.pairs_after >= result_.pairs_before) {  // nothing gained: all stays as it was
      result_.patches.clear();
      result_.pairs_after = result_.pairs_before;
      facets_.resize(mesh_.num_faces());
      origin_.resize(mesh_.num_faces());
      for (uint32_t f = 0; f < mesh_.num_faces(); ++f) {
        facets_[f] = {mesh_.triangles[3 * f], mesh_.triangles[3 * f + 1],
                      mesh_.triangles[3 * f + 2]};
        origin_[f] = f;
      }
      Leave(given);
      return std::move(result_);
    }
    Leave(lists);
    Write();
    return std::move(result_);
  }

 private:
  DVec3 Pos(uint32_t v) const {
    const float* p = &mesh_.positions[3 * size_t{v}];
    return {p[0], p[1], p[2]};
  }
  FacetBox BoxOf(const Facet& t) const { return FacetBoxOf(mesh_.positions, t.data()); }
  DVec3 AreaVector(const Facet& t) const {
    return 0.5 * Cross(Pos(t[1]) - Pos(t[0]), Pos(t[2]) - Pos(t[0]));
  }
  // The facets with the vertices they use (renumbered in order of use).
  RawMesh Soup(const std::vector<Facet>& facets) const {
    RawMesh soup;
    soup.origin = mesh_.origin;
    soup.triangles.reserve(3 * facets.size());
    absl::flat_hash_map<uint32_t, uint32_t> index;
    for (const Facet& t : facets)
      for (uint32_t v : t) {
        const auto [it, fresh] = index.try_emplace(v, uint32_t(index.size()));
        if (fresh)
          soup.positions.insert(soup.positions.end(), &mesh_.positions[3 * size_t{v}],
                                &mesh_.positions[3 * size_t{v}] + 3);
        soup.triangles.push_back(it->second);
      }
    return soup;
  }

  // Facets per vertex, edge-connected components and their areas: of facets_ now. An edge's
  // facets are found among those of its vertex with fewer (a few; a fan's apex may have
  // thousands, its rim vertices not), not in a table of all edges: on a mesh of a million facets
  // the two tables took a second.
  void Index() {
    const size_t nf = facets_.size();
    const size_t nv = mesh_.num_vertices();
    vertex_begin_.assign(nv + 1, 0);
    for (const Facet& t : facets_)
      for (uint32_t v : t) ++vertex_begin_[v + 1];
    for (size_t v = 0; v < nv; ++v) vertex_begin_[v + 1] += vertex_begin_[v];
    vertex_facets_.resize(3 * nf);
    std::vector<uint32_t> fill(vertex_begin_.begin(), vertex_begin_.end() - 1);
    for (uint32_t f = 0; f < nf; ++f)
      for (uint32_t v : facets_[f]) vertex_facets_[fill[v]++] = f;
    UnionFind parts(nf);
    for (uint32_t f = 0; f < nf; ++f)
      for (int i = 0; i < 3; ++i) {
        const auto [a, b] = FewerFacetsFirst(facets_[f][i], facets_[f][(i + 1) % 3]);
        for (uint32_t k = vertex_begin_[a]; k < vertex_begin_[a + 1]; ++k) {
          const uint32_t g = vertex_facets_[k];
          if (g > f && Uses(facets_[g], b)) parts.Union(f, g);
        }
      }
    component_.resize(nf);
    component_area_.assign(nf, 0.0);
    for (uint32_t f = 0; f < nf; ++f) {
      component_[f] = parts.Find(f);
      component_area_[component_[f]] += Norm(AreaVector(facets_[f]));
    }
  }
  // Drops the pairs of two surfaces where only those of one are taken out (facets_ now).
  void InScope(std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
    if (scope_ == CrossingScope::kAll || pairs.empty()) return;
    Index();
    std::erase_if(pairs,
                  [&](const auto& p) { return component_[p.first] != component_[p.second]; });
  }
  static bool Uses(const Facet& t, uint32_t v) { return t[0] == v || t[1] == v || t[2] == v; }
  std::pair<uint32_t, uint32_t> FewerFacetsFirst(uint32_t a, uint32_t b) const {
    const uint32_t at_a = vertex_begin_[a + 1] - vertex_begin_[a];
    return at_a <= vertex_begin_[b + 1] - vertex_begin_[b] ? std::pair(a, b) : std::pair(b, a);
  }
  // How many facets use the edge u-v, either way.
  uint32_t EdgeUses(uint32_t u, uint32_t v) const {
    const auto [a, b] = FewerFacetsFirst(u, v);
    uint32_t n = 0;
    for (uint32_t k = vertex_begin_[a]; k < vertex_begin_[a + 1]; ++k)
      n += Uses(facets_[vertex_facets_[k]], b);
    return n;
  }

  // The facets at vertex v, in facet order.
  std::vector<uint32_t> Star(uint32_t v) const {
    std::vector<uint32_t> star(vertex_facets_.begin() + vertex_begin_[v],
                               vertex_facets_.begin() + vertex_begin_[v + 1]);
    std::sort(star.begin(), star.end());
    return star;
  }

  // How far v lies from the centre of its ring, over the ring's mean radius: a vertex written
  // wrongly lies far off its neighbours; one of a surface, near their middle.
  double Offset(uint32_t v) const {
    std::vector<uint32_t> ring;
    for (uint32_t f : Star(v))
      for (uint32_t u : facets_[f])
        if (u != v) ring.push_back(u);
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    if (ring.empty()) return 0;
    DVec3 c{0, 0, 0};
    for (uint32_t u : ring) c += (1.0 / ring.size()) * Pos(u);
    double radius = 0;
    for (uint32_t u : ring) radius += Norm(Pos(u) - c) / ring.size();
    return radius > 0 ? Norm(Pos(v) - c) / radius : 0;
  }

  // Per cluster of crossing facets (linked by the pairs; of one surface or of two: a vertex may
  // poke into another body or a cavity), vertices of theirs taken out with their facets, where
  // their facets hold a facet of every pair of the cluster and the rim closes without a new
  // crossing: one vertex where one does (of several, the one farthest off its ring), else
  // the vertices farthest off their rings, one after another, until their facets hold every
  // pair (vertices written wrongly side by side). Whether any was taken out.
  bool TakeOutVertices(const std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
    Index();
    std::vector<FacetBox> boxes(facets_.size());
    for (size_t f = 0; f < facets_.size(); ++f) boxes[f] = BoxOf(facets_[f]);
    grid_.emplace(std::move(boxes));
    UnionFind clusters(facets_.size());
    for (const auto& [a, b] : pairs) clusters.Union(a, b);
    absl::flat_hash_map<uint32_t, std::vector<std::pair<uint32_t, uint32_t>>> by_cluster;
    for (const auto& pair : pairs) by_cluster[clusters.Find(pair.first)].push_back(pair);
    std::vector<Plan> chosen;
    std::vector<char> out(facets_.size(), 0);
    std::vector<uint32_t> roots;
    for (const auto& [root, list] : by_cluster) roots.push_back(root);
    std::sort(roots.begin(), roots.end());
    // The plan taking out `facets`, where it closes without meeting anything; else none.
    const auto try_patch = [&](std::vector<uint32_t> facets) -> std::optional<Plan> {
      if (OverBudget() ||
          std::any_of(facets.begin(), facets.end(), [&](uint32_t f) { return out[f] != 0; }))
        return std::nullopt;
      std::vector<Plan> trial{PlanFill(std::move(facets))};
      if (!trial[0].refused.empty()) return std::nullopt;
      for (const Plan& p : chosen) trial.push_back(p);
      // Out for the check only (a copy of `out` per try would read every facet).
      for (uint32_t f : trial[0].facets) out[f] = 1;
      const bool meets = FillMeetsSomething(trial, 0, out);
      for (uint32_t f : trial[0].facets) out[f] = 0;
      if (meets) return std::nullopt;
      return std::move(trial[0]);
    };
    for (uint32_t root : roots) {
      const auto& list = by_cluster.at(root);
      // A vertex's facets cross a few dozen at most: a larger cluster is bodies overlapping.
      if (list.size() > kMaxVertexPairs || OverBudget()) continue;
      std::vector<uint32_t> candidates;
      for (const auto& [a, b] : list)
        for (uint32_t f : {a, b})
          candidates.insert(candidates.end(), facets_[f].begin(), facets_[f].end());
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      std::optional<Plan> best;
      double best_offset = -1;
      for (uint32_t v : candidates) {
        std::vector<uint32_t> star = Star(v);
        const auto holds = [&](uint32_t f) {
          return std::binary_search(star.begin(), star.end(), f);
        };
        if (!std::all_of(list.begin(), list.end(),
                         [&](const auto& p) { return holds(p.first) || holds(p.second); }))
          continue;
        std::optional<Plan> plan = try_patch(std::move(star));
        if (!plan) continue;
        if (const double offset = Offset(v); offset > best_offset) {
          best = std::move(plan);
          best_offset = offset;
        }
      }
      if (!best) {
        std::vector<std::pair<double, uint32_t>> by_offset;
        for (uint32_t v : candidates) by_offset.push_back({-Offset(v), v});
        std::sort(by_offset.begin(), by_offset.end());
        std::vector<std::pair<uint32_t, uint32_t>> left = list;
        std::vector<uint32_t> patch;
        for (const auto& [offset, v] : by_offset) {
          if (left.empty() || patch.size() > kMaxLoopEdges) break;
          const std::vector<uint32_t> star = Star(v);
          const auto holds = [&](uint32_t f) {
            return std::binary_search(star.begin(), star.end(), f);
          };
          if (std::erase_if(left,
                            [&](const auto& p) { return holds(p.first) || holds(p.second); }) == 0)
            continue;
          patch.insert(patch.end(), star.begin(), star.end());
        }
        std::sort(patch.begin(), patch.end());
        patch.erase(std::unique(patch.begin(), patch.end()), patch.end());
        if (left.empty()) best = try_patch(std::move(patch));
      }
      if (!best) continue;
      for (uint32_t f : best->facets) out[f] = 1;
      chosen.push_back(*std::move(best));
    }
    if (chosen.empty()) return false;
    Apply(chosen);
    return true;
  }

  Plan PlanFill(std::vector<uint32_t> facets) const {
    Plan plan;
    plan.facets = std::move(facets);
    UncrossedPatch& patch = plan.patch;
    patch.facets_removed = plan.facets.size();
    uint32_t lowest = UINT32_MAX;
    for (uint32_t f : plan.facets) lowest = std::min(lowest, origin_[f]);
    patch.first_facet = lowest;
    {
      DVec3 c{0, 0, 0};
      for (uint32_t v : facets_[plan.facets[0]]) c += (1.0 / 3) * Pos(v);
      patch.at = {c.x, c.y, c.z};
    }
    // Its edges: how often the patch uses each, against the whole surface's uses.
    absl::flat_hash_map<uint64_t, uint32_t> inner;
    absl::flat_hash_set<uint32_t> vertices;
    for (uint32_t f : plan.facets)
      for (int i = 0; i < 3; ++i) {
        ++inner[EdgeKey(facets_[f][i], facets_[f][(i + 1) % 3])];
        vertices.insert(facets_[f][i]);
      }
    for (const auto& [key, n] : inner)
      if (EdgeUses(uint32_t(key >> 32), uint32_t(key)) != 2) {
        plan.refused = "its facets reach an open edge or a seam of the surface";
        return plan;
      }
    // Its rim: the edges it uses once, as its facets run them; one simple loop, and the patch a
    // disc (Euler characteristic 1), so that closing the loop keeps the surface's topology.
    absl::flat_hash_map<uint32_t, uint32_t> next;
    for (uint32_t f : plan.facets)
      for (int i = 0; i < 3; ++i) {
        const uint32_t a = facets_[f][i], b = facets_[f][(i + 1) % 3];
        if (inner.at(EdgeKey(a, b)) == 1 && !next.try_emplace(a, b).second) {
          plan.refused = "its rim passes a vertex twice";
          return plan;
        }
      }
    if (int64_t(vertices.size()) - int64_t(inner.size()) + int64_t(plan.facets.size()) != 1 ||
        next.empty()) {
      plan.refused = "it is not a disc (it wraps around a handle or holds a hole)";
      return plan;
    }
    // From its lowest vertex, so that the fill does not depend on the map's order.
    uint32_t start = UINT32_MAX;
    for (const auto& [from, to] : next) start = std::min(start, from);
    std::vector<uint32_t> loop{start};
    while (loop.size() <= next.size()) {
      const auto after = next.find(loop.back());
      if (after == next.end() || after->second == loop.front()) break;
      loop.push_back(after->second);
    }
    if (loop.size() != next.size()) {
      plan.refused = "its rim is not one loop";
      return plan;
    }
    const size_t n = loop.size();
    patch.loop_edges = n;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j)
        patch.across = std::max(patch.across, Norm(Pos(loop[i]) - Pos(loop[j])));
    if (n > kMaxLoopEdges) {
      plan.refused =
          absl::StrFormat("its rim is %u edges long (at most %u are closed)", n, kMaxLoopEdges);
      return plan;
    }
    const auto area = [&](size_t i, size_t k, size_t j) {
      return Norm(AreaVector({loop[i], loop[k], loop[j]}));
    };
    const auto taken = [&](size_t i, size_t j) {  // an edge the mesh keeps outside the patch
      const auto own = inner.find(EdgeKey(loop[i], loop[j]));
      return EdgeUses(loop[i], loop[j]) > (own == inner.end() ? 0u : own->second);
    };
    // Seen along the rim's normal, a vertex's ring is a simple polygon: every new facet must
    // turn its way, so that the fill stays inside it (a diagonal outside a ring that bends
    // around a hole would close the hole).
    std::vector<std::array<double, 3>> corners;
    for (uint32_t v : loop) corners.push_back({Pos(v).x, Pos(v).y, Pos(v).z});
    const std::array<double, 3> nn = NewellNormal(corners.data(), n);
    const DVec3 normal{nn[0], nn[1], nn[2]};
    const auto turns_along = [&](size_t i, size_t k, size_t j) {
      const DVec3 c = Cross(Pos(loop[k]) - Pos(loop[i]), Pos(loop[j]) - Pos(loop[i]));
      return Dot(c, normal) > 1e-6 * Norm(c) * Norm(normal);
    };
    const LeastAreaFill least = LeastAreaTriangulation(
        n,
        [&](size_t i, size_t k, size_t j) {
          const float* p = &mesh_.positions[0];
          return !((k > i + 1 && taken(i, k)) || (j > k + 1 && taken(k, j)) ||
                   IsZeroArea(p + 3 * size_t{loop[i]}, p + 3 * size_t{loop[k]},
                              p + 3 * size_t{loop[j]}) ||
                   !turns_along(i, k, j));
        },
        area);
    if (least.triangles.empty()) {
      plan.refused = absl::StrFormat(
          "no triangulation of its rim of %u edges stays inside it (seen along its normal) and "
          "avoids the surface's edges and zero areas",
          n);
      return plan;
    }
    const double surface_area = component_area_[component_[plan.facets[0]]];
    if (least.area > kMaxFillShare * surface_area) {
      plan.refused =
          absl::StrFormat("closing its rim would take %.3g%% of its surface's area (at most %g%%)",
                          100 * least.area / surface_area, 100 * kMaxFillShare);
      return plan;
    }
    // Volume change: both sides share the rim, so the difference of their cones from one point
    // is the volume between them.
    DVec3 apex{0, 0, 0};
    for (uint32_t v : loop) apex += (1.0 / n) * Pos(v);
    const auto cone = [&](const Facet& t) {
      return Dot(Pos(t[0]) - apex, Cross(Pos(t[1]) - apex, Pos(t[2]) - apex)) / 6;
    };
    for (uint32_t f : plan.facets) {
      patch.area_removed += Norm(AreaVector(facets_[f]));
      patch.volume_change -= cone(facets_[f]);
    }
    for (const auto& [i, k, j] : least.triangles) {
      const Facet t{loop[i], loop[k], loop[j]};
      plan.fill.push_back(t);
      patch.area_added += Norm(AreaVector(t));
      patch.volume_change += cone(t);
      // Group and fields: of the facet taken out nearest to it.
      const DVec3 c = (1.0 / 3) * (Pos(t[0]) + Pos(t[1]) + Pos(t[2]));
      uint32_t best = plan.facets[0];
      double best_d = HUGE_VAL;
      for (uint32_t f : plan.facets) {
        const DVec3 d =
            (1.0 / 3) * (Pos(facets_[f][0]) + Pos(facets_[f][1]) + Pos(facets_[f][2])) - c;
        if (Dot(d, d) < best_d) {
          best_d = Dot(d, d);
          best = f;
        }
      }
      plan.fill_origin.push_back(origin_[best]);
    }
    patch.facets_added = plan.fill.size();
    const absl::flat_hash_set<uint32_t> rim(loop.begin(), loop.end());
    for (uint32_t v : vertices) {
      if (rim.contains(v)) continue;
      ++patch.vertices_dropped;
      double nearest = HUGE_VAL;
      for (const Facet& t : plan.fill)
        nearest =
            std::min(nearest, SquaredDistanceToTriangle(Pos(v), Pos(t[0]), Pos(t[1]), Pos(t[2])));
      patch.farthest = std::max(patch.farthest, std::sqrt(nearest));
    }
    return plan;
  }

  // Whether plan i's new facets cross, overlap or fold onto the facets kept or the other plans'
  // new facets within their box (`out`: the facets the plans take out).
  bool FillMeetsSomething(const std::vector<Plan>& plans, size_t i, const std::vector<char>& out) {
    FacetBox box = BoxOf(plans[i].fill[0]);
    for (const Facet& t : plans[i].fill) {
      const FacetBox b = BoxOf(t);
      for (int k = 0; k < 3; ++k) {
        box.lo[k] = std::min(box.lo[k], b.lo[k] - tolerance_);
        box.hi[k] = std::max(box.hi[k], b.hi[k] + tolerance_);
      }
    }
    std::vector<uint32_t> near;
    work_ += double(grid_->ForEachMeeting(box, [&](uint32_t f) {
      if (!out[f]) near.push_back(f);
    }));
    std::sort(near.begin(), near.end());  // the check's soup in facet order, as it always was
    std::vector<Facet> local;
    for (uint32_t f : near) local.push_back(facets_[f]);
    for (size_t j = 0; j < plans.size(); ++j)
      if (j != i && plans[j].refused.empty())
        for (const Facet& t : plans[j].fill)
          if (BoxOf(t).Meets(box)) local.push_back(t);
    const uint32_t own = uint32_t(local.size());
    local.insert(local.end(), plans[i].fill.begin(), plans[i].fill.end());
    CrossingPairLists found;
    FindCrossings(Soup(local), {.lists = &found});
    for (const auto* pairs : {&found.crossing, &found.overlapping, &found.folded})
      for (const auto& [a, b] : *pairs)
        if (a >= own || b >= own) return true;
    return false;
  }

  bool SameFacets(const Plan& p) const {
    if (p.fill.size() != p.facets.size()) return false;
    const auto canonical = [](Facet t) {
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      return t;
    };
    std::vector<Facet> before, after;
    for (uint32_t f : p.facets) before.push_back(canonical(facets_[f]));
    for (const Facet& t : p.fill) after.push_back(canonical(t));
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    return before == after;
  }

  // The plans not refused replace their facets: the kept facets in their order, then the fills.
  void Apply(const std::vector<Plan>& plans) {
    std::vector<char> out(facets_.size(), 0);
    for (const Plan& p : plans)
      if (p.refused.empty())
        for (uint32_t f : p.facets) out[f] = 1;
    std::vector<Facet> facets;
    std::vector<uint32_t> origin;
    for (uint32_t f = 0; f < facets_.size(); ++f)
      if (!out[f]) {
        facets.push_back(facets_[f]);
        origin.push_back(origin_[f]);
      }
    for (const Plan& p : plans) {
      if (!p.refused.empty()) continue;
      facets.insert(facets.end(), p.fill.begin(), p.fill.end());
      origin.insert(origin.end(), p.fill_origin.begin(), p.fill_origin.end());
      // A patch closed again as it was (a wall a crossing passed through, its facets fine) is
      // no change to report.
      if (!SameFacets(p)) result_.patches.push_back(p.patch);
    }
    facets_ = std::move(facets);
    origin_ = std::move(origin);
  }

  // What still crosses, once per surface crossing itself and per two surfaces crossing each
  // other, with why no vertex took it out.
  void Leave(const CrossingPairLists& lists) {
    if (lists.crossing.empty()) return;
    Index();
    struct Cluster {
      size_t pairs = 0;
      bool two_surfaces = false;
      uint32_t first = UINT32_MAX;  // its lowest facet of the mesh given
      uint32_t at = 0;              // a facet of its first pair
    };
    absl::flat_hash_map<uint64_t, Cluster> by_root;
    for (const auto& [a, b] : lists.crossing) {
      Cluster& c = by_root[EdgeKey(component_[a], component_[b])];
      if (c.pairs++ == 0) c.at = a;
      c.two_surfaces = component_[a] != component_[b];
      c.first = std::min({c.first, origin_[a], origin_[b]});
    }
    std::vector<uint64_t> roots;
    for (const auto& [root, c] : by_root) roots.push_back(root);
    std::sort(roots.begin(), roots.end());
    for (uint64_t root : roots) {
      const Cluster& c = by_root.at(root);
      const std::string why = OverBudget() ? kTooMany
                              : c.pairs > kMaxVertexPairs
                                  ? "more pairs than a vertex written wrongly makes"
                                  : "no vertex of theirs taken out with its facets frees "
                                    "them without a new crossing";
      DVec3 centre{0, 0, 0};
      for (uint32_t v : facets_[c.at]) centre += (1.0 / 3) * Pos(v);
      result_.left.push_back(
          {c.first,
           {centre.x, centre.y, centre.z},
           absl::StrFormat("%s cross each other (%u face pairs; %s); left as they are: %s",
                           c.two_surfaces ? "two surfaces" : "facets of one surface", c.pairs,
                           c.two_surfaces ? "bodies exported overlapping (--unite-overlaps "
                                            "replaces closed ones by their union), a body "
                                            "written twice, its copy farther off than "
                                            "--duplicate-body-offset takes, or a part and its "
                                            "cavity's wall"
                                          : "a thin wall tessellated coarser than its thickness",
                           why)});
    }
  }

  // The result, a copy of the mesh given with the facets replaced (made only where they change).
  void Write() {
    result_.facet_origin = origin_;
    RawMesh& m = result_.mesh;
    m = mesh_;
    m.triangles.clear();
    for (const Facet& t : facets_) m.triangles.insert(m.triangles.end(), t.begin(), t.end());
    if (!m.face_groups.empty()) {
      std::vector<uint32_t> groups(origin_.size());
      for (size_t f = 0; f < origin_.size(); ++f) groups[f] = m.face_groups[origin_[f]];
      m.face_groups = std::move(groups);
    }
    for (FaceField& field : m.face_fields) {
      std::vector<float> values(origin_.size());
      for (size_t f = 0; f < origin_.size(); ++f) values[f] = field.values[origin_[f]];
      field.values = std::move(values);
    }
  }

  WorkerPool* pool() { return pool_ ? &*pool_ : nullptr; }

  const RawMesh& mesh_;
  const int threads_;
  const CrossingScope scope_;
  std::optional<WorkerPool> pool_;  // the whole mesh's scans run on it
  std::vector<Facet> facets_;
  std::vector<uint32_t> origin_;
  std::vector<uint32_t> component_;
  std::vector<double> component_area_;
  std::vector<uint32_t> vertex_begin_, vertex_facets_;
  std::optional<FacetBoxGrid> grid_;  // facets_'s boxes, while TakeOutVertices tries fills
  // Each fill's check reads the facets in its box's cells: the entries read so far, against a
  // budget that keeps a soup crossing itself everywhere from taking minutes.
  bool OverBudget() const { return work_ > kMaxFacetReads; }
  static constexpr double kMaxFacetReads = 2e8;
  static constexpr size_t kMaxVertexPairs = 256;
  static constexpr const char* kTooMany =
      "too many crossings to take out one by one (bodies overlapping, or a soup)";
  double work_ = 0;
  double tolerance_ = 0;
  UncrossResult result_;
};

}  // namespace

UncrossResult TakeOutCrossings(const RawMesh& mesh, int threads, CrossingScope scope) {
  return Uncrosser(mesh, threads, scope).Run();
}

}  // namespace femsimp
