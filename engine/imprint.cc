#include "engine/imprint.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <numeric>
#include <optional>
#include <utility>
#include <variant>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"
#include "engine/crossings.h"
#include "engine/union_find.h"

namespace femsimp {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
// Rounds of finding contacts and imprinting those that share no vertex with one imprinted in the
// same round; contacts that meet (a plate's top under a block, the block's side against another
// block) take one round each.
constexpr int kMaxRounds = 16;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexInfo {
  uint32_t mesh = kNone;  // the mesh's vertex at this point (kNone: where constraints cross)
};
struct FaceInfo {
  uint32_t stamp = 0;  // the last facet whose inside the walk reached this face from
  uint32_t covers = 0;
  uint32_t cover[2] = {kNone, kNone};  // the facets (indices into the contact) over this face
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact predicates, rounded intersection points: the bodies' edges cross inside the contact.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Cdtp = CGAL::Constrained_triangulation_plus_2<Cdt>;
using VertexHandle = Cdtp::Vertex_handle;
using FaceHandle = Cdtp::Face_handle;

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  return a < b ? uint64_t{a} << 32 | b : uint64_t{b} << 32 | a;
}

// Whether every corner of facets a and b lies within `tolerance` of the other's plane.
bool InOnePlane(const RawMesh& mesh, uint32_t a, uint32_t b, double tolerance) {
  const auto near = [&](uint32_t of, uint32_t other) {
    const uint32_t* t = &mesh.triangles[3 * size_t{of}];
    const float* p[3] = {&mesh.positions[3 * size_t{t[0]}], &mesh.positions[3 * size_t{t[1]}],
                         &mesh.positions[3 * size_t{t[2]}]};
    const double e[3] = {double{p[1][0]} - p[0][0], double{p[1][1]} - p[0][1],
                         double{p[1][2]} - p[0][2]};
    const double g[3] = {double{p[2][0]} - p[0][0], double{p[2][1]} - p[0][1],
                         double{p[2][2]} - p[0][2]};
    const double n[3] = {e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2],
                         e[0] * g[1] - e[1] * g[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (length == 0.0) return false;
    for (int c = 0; c < 3; ++c) {
      const float* q = &mesh.positions[3 * size_t{mesh.triangles[3 * size_t{other} + c]}];
      const double d =
          (n[0] * (q[0] - p[0][0]) + n[1] * (q[1] - p[0][1]) + n[2] * (q[2] - p[0][2])) / length;
      if (std::fabs(d) > 2.0 * tolerance) return false;
    }
    return true;
  };
  return near(a, b) && near(b, a);
}

// One contact re-tiled: what replaces its facets, before it is written into the mesh.
struct Retiling {
  std::vector<std::array<uint32_t, 3>> facets;        // mesh vertices; added points from next_point
  std::vector<uint32_t> facet_of;                     // per new facet: the mesh's facet it lies in
  std::vector<std::array<float, 3>> points;           // the added points, in order
  std::vector<std::pair<uint32_t, uint32_t>> merged;  // (corner, the other body's corner it is)
  // Per edge of the contact's facets that the re-tiling cut: the vertices along it, from its
  // lower-numbered end to the other (ends included).
  absl::flat_hash_map<uint64_t, std::vector<uint32_t>> cut_edges;
  ImprintedContact contact;
};

class ContactRetiler {
 public:
  ContactRetiler(const RawMesh& mesh, const std::vector<uint32_t>& facets, double plane_tolerance,
                 uint32_t next_point)
      : mesh_(mesh), facets_(facets), tolerance_(plane_tolerance), next_point_(next_point) {}

  // The re-tiling, or why the contact is left as it was.
  std::variant<Retiling, std::string> Run();

 private:
  std::array<double, 3> Pos(uint32_t v) const {
    const float* p = &mesh_.positions[3 * size_t{v}];
    return {p[0], p[1], p[2]};
  }
  uint32_t Corner(size_t i, int c) const { return mesh_.triangles[3 * size_t{facets_[i]} + c]; }
  K::Point_2 InPlane(uint32_t v) const {
    const std::array<double, 3> p = Pos(v);
    return {p[u_], p[w_]};
  }
  // The vertices along the edge from p to q (ends included).
  std::vector<VertexHandle> Along(VertexHandle p, VertexHandle q);

  const RawMesh& mesh_;
  const std::vector<uint32_t>& facets_;
  const double tolerance_;
  uint32_t next_point_;
  int k_ = 2, u_ = 0, w_ = 1;  // the axis the plane is seen along, and the plane's two
  Cdtp cdt_;
  // Per edge of a facet: the corners it runs through (its ends and the corners on it), from
  // one end; per piece between two of them: its constraint and the end it was inserted from.
  absl::flat_hash_map<uint64_t, std::vector<VertexHandle>> chains_;
  absl::flat_hash_map<uint64_t, std::pair<Cdtp::Constraint_id, VertexHandle>> constraints_;
  absl::flat_hash_map<uint64_t, std::vector<VertexHandle>> along_;  // Along's, from chains_' end
};

std::vector<VertexHandle> ContactRetiler::Along(VertexHandle p, VertexHandle q) {
  const uint64_t key = EdgeKey(p->info().mesh, q->info().mesh);
  auto [it, fresh] = along_.try_emplace(key);
  std::vector<VertexHandle>& along = it->second;
  if (fresh) {
    const std::vector<VertexHandle>& corners = chains_.at(key);
    along.push_back(corners.front());
    for (size_t j = 0; j + 1 < corners.size(); ++j) {
      const auto& [cid, first] =
          constraints_.at(EdgeKey(corners[j]->info().mesh, corners[j + 1]->info().mesh));
      std::vector<VertexHandle> piece(cdt_.vertices_in_constraint_begin(cid),
                                      cdt_.vertices_in_constraint_end(cid));
      if (first != corners[j]) std::reverse(piece.begin(), piece.end());
      along.insert(along.end(), piece.begin() + 1, piece.end());
    }
  }
  if (along.front() == p) return along;
  return std::vector<VertexHandle>(along.rbegin(), along.rend());
}

std::variant<Retiling, std::string> ContactRetiler::Run() {
  Retiling out;
  // The plane: the largest facet's, seen along its normal's largest axis (u, w, k right-handed,
  // so that a facet facing +k winds counter-clockwise in (u, w)).
  double normal[3] = {0, 0, 0}, offset = 0, largest = -1;
  for (size_t i = 0; i < facets_.size(); ++i) {
    const std::array<double, 3> a = Pos(Corner(i, 0)), b = Pos(Corner(i, 1)), c = Pos(Corner(i, 2));
    const double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double g[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2],
                         e[0] * g[1] - e[1] * g[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (length <= largest) continue;
    largest = length;
    for (int d = 0; d < 3; ++d) normal[d] = n[d] / length;
    offset = normal[0] * a[0] + normal[1] * a[1] + normal[2] * a[2];
  }
  k_ = 0;
  for (int d = 1; d < 3; ++d)
    if (std::fabs(normal[d]) > std::fabs(normal[k_])) k_ = d;
  u_ = (k_ + 1) % 3;
  w_ = (k_ + 2) % 3;
  for (size_t i = 0; i < facets_.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const std::array<double, 3> p = Pos(Corner(i, c));
      if (std::fabs(normal[0] * p[0] + normal[1] * p[1] + normal[2] * p[2] - offset) >
          2.0 * tolerance_)
        return absl::StrCat("facet ", facets_[i], " lies off the contact's plane");
    }

  // Corners: points of the plane within the tolerance of each other are one (the bodies' copies
  // of a corner, apart by their exports' rounding), the lowest-numbered vertex standing for them.
  std::vector<uint32_t> corners;
  for (size_t i = 0; i < facets_.size(); ++i)
    for (int c = 0; c < 3; ++c) corners.push_back(Corner(i, c));
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  const double snap = tolerance_;
  const auto cell_of = [](const K::Point_2& p, double size) {
    return std::pair(int64_t(std::floor(p.x() / size)), int64_t(std::floor(p.y() / size)));
  };
  absl::flat_hash_map<uint32_t, VertexHandle> handle;
  std::vector<uint32_t> reps;
  {
    absl::flat_hash_map<std::pair<int64_t, int64_t>, std::vector<uint32_t>> near;
    for (uint32_t v : corners) {
      const K::Point_2 p = InPlane(v);
      const auto [cx, cy] = cell_of(p, snap);
      uint32_t into = kNone;
      for (int64_t dx = -1; dx <= 1 && into == kNone; ++dx)
        for (int64_t dy = -1; dy <= 1 && into == kNone; ++dy)
          if (const auto it = near.find(std::pair(cx + dx, cy + dy)); it != near.end())
            for (uint32_t r : it->second)
              if (CGAL::squared_distance(p, InPlane(r)) <= snap * snap) {
                into = r;
                break;
              }
      if (into == kNone) {
        near[std::pair(cx, cy)].push_back(v);
        const VertexHandle h = cdt_.insert(p);
        h->info().mesh = v;
        handle[v] = h;
        reps.push_back(v);
        continue;
      }
      const std::array<double, 3> a = Pos(v), b = Pos(into);
      if (std::fabs(a[k_] - b[k_]) > 2.0 * tolerance_)
        return absl::StrCat("vertices ", into, " and ", v,
                            " coincide in the contact's plane but lie ", std::fabs(a[k_] - b[k_]),
                            " apart across it");
      handle[v] = handle[into];
      out.merged.emplace_back(v, into);
    }
  }
  // Which way each facet winds in the plane: the side its inside lies on.
  std::vector<int> sign(facets_.size());
  double edge_length = 0;
  for (size_t i = 0; i < facets_.size(); ++i) {
    const K::Point_2 &a = handle[Corner(i, 0)]->point(), &b = handle[Corner(i, 1)]->point(),
                     &c = handle[Corner(i, 2)]->point();
    const CGAL::Orientation o = CGAL::orientation(a, b, c);
    if (o == CGAL::COLLINEAR)
      return absl::StrCat("facet ", facets_[i], " has no area in the contact's plane");
    sign[i] = o == CGAL::LEFT_TURN ? 1 : -1;
    edge_length += std::sqrt(CGAL::squared_distance(a, b));
  }
  // Edges: a corner within the tolerance of another edge lies on it (the edge is cut there and
  // bends by the tolerance at most), so that no sliver that thin is made where a body's corner
  // stands on the other's edge.
  const double cell = std::max(snap, edge_length / double(facets_.size()));
  absl::flat_hash_map<std::pair<int64_t, int64_t>, std::vector<uint32_t>> by_cell;
  for (uint32_t r : reps) by_cell[cell_of(InPlane(r), cell)].push_back(r);
  for (size_t i = 0; i < facets_.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const VertexHandle a = handle[Corner(i, c)], b = handle[Corner(i, (c + 1) % 3)];
      const uint64_t key = EdgeKey(a->info().mesh, b->info().mesh);
      if (a == b || chains_.contains(key)) continue;
      const K::Point_2 &pa = a->point(), &pb = b->point();
      const double length = std::sqrt(CGAL::squared_distance(pa, pb));
      const auto lo =
          cell_of({std::min(pa.x(), pb.x()) - snap, std::min(pa.y(), pb.y()) - snap}, cell);
      const auto hi =
          cell_of({std::max(pa.x(), pb.x()) + snap, std::max(pa.y(), pb.y()) + snap}, cell);
      std::vector<std::pair<double, uint32_t>> on;
      if ((hi.first - lo.first + 1) * (hi.second - lo.second + 1) <=
          int64_t(4 * reps.size() + 16)) {
        for (int64_t x = lo.first; x <= hi.first; ++x)
          for (int64_t y = lo.second; y <= hi.second; ++y) {
            const auto it = by_cell.find(std::pair(x, y));
            if (it == by_cell.end()) continue;
            for (uint32_t r : it->second) {
              const K::Point_2 p = InPlane(r);
              const double t =
                  ((p.x() - pa.x()) * (pb.x() - pa.x()) + (p.y() - pa.y()) * (pb.y() - pa.y())) /
                  (length * length);
              if (t * length <= snap || (1 - t) * length <= snap) continue;
              const K::Point_2 foot(pa.x() + t * (pb.x() - pa.x()), pa.y() + t * (pb.y() - pa.y()));
              if (CGAL::squared_distance(p, foot) <= snap * snap) on.emplace_back(t, r);
            }
          }
      }
      std::sort(on.begin(), on.end());
      std::vector<VertexHandle> chain = {a};
      for (const auto& [t, r] : on) chain.push_back(handle[r]);
      chain.push_back(b);
      for (size_t j = 0; j + 1 < chain.size(); ++j) {
        const uint64_t piece = EdgeKey(chain[j]->info().mesh, chain[j + 1]->info().mesh);
        if (constraints_.contains(piece)) continue;
        const Cdtp::Constraint_id cid = cdt_.insert_constraint(chain[j], chain[j + 1]);
        if (cid == Cdtp::Constraint_id(nullptr))
          return absl::StrCat("an edge of facet ", facets_[i], " could not be a constraint");
        constraints_[piece] = {cid, chain[j]};
      }
      chains_[key] = std::move(chain);
    }
  // Points where the bodies' edges cross, lifted onto the plane.
  for (auto v = cdt_.finite_vertices_begin(); v != cdt_.finite_vertices_end(); ++v) {
    if (v->info().mesh != kNone) continue;
    v->info().mesh = next_point_++;
    std::array<float, 3> p;
    p[u_] = float(v->point().x());
    p[w_] = float(v->point().y());
    p[k_] = float((offset - normal[u_] * p[u_] - normal[w_] * p[w_]) / normal[k_]);
    out.points.push_back(p);
  }

  // Each facet's inside: the faces reached from its edges' inner sides without crossing them.
  for (size_t i = 0; i < facets_.size(); ++i) {
    std::vector<VertexHandle> loop;  // its boundary, inside on the left, as the pieces run
    for (int c = 0; c < 3; ++c) {
      const int from = sign[i] > 0 ? c : (3 - c) % 3, to = sign[i] > 0 ? (c + 1) % 3 : (2 - c) % 3;
      const VertexHandle p = handle[Corner(i, from)], q = handle[Corner(i, to)];
      if (p == q) continue;
      const std::vector<VertexHandle> along = Along(p, q);
      loop.insert(loop.end(), along.begin(), along.end() - 1);
    }
    // A corner on two edges near the facet's corner between them (an acute corner) makes the
    // loop run out to that corner and back: no area, and no inside to its sides.
    for (bool spiked = true; spiked && loop.size() > 2;) {
      spiked = false;
      for (size_t j = 0; j < loop.size() && !spiked; ++j)
        if (loop[(j + loop.size() - 1) % loop.size()] == loop[(j + 1) % loop.size()]) {
          const size_t next = (j + 1) % loop.size();
          loop.erase(loop.begin() + std::max(j, next));
          loop.erase(loop.begin() + std::min(j, next));
          spiked = true;
        }
    }
    if (loop.size() < 3) continue;
    double expected = 0, longest = 0;  // the area the loop winds around (shoelace)
    for (size_t j = 0; j < loop.size(); ++j) {
      const K::Point_2 &a = loop[j]->point(), &b = loop[(j + 1) % loop.size()]->point();
      expected += (a.x() * b.y() - b.x() * a.y()) / 2;
      longest = std::max(longest, CGAL::squared_distance(a, b));
    }
    // A sliver thinner than the tolerance whose apex lies on its own base once the corners
    // are on the edges: its boundary runs there and back, and the facet beside it takes its
    // place.
    if (std::fabs(expected) <= 1e-9 * longest) continue;
    if (expected < 0)
      return absl::StrCat("facet ", facets_[i], " turns over once its corners are on the edges");
    std::vector<uint64_t> own;  // a few edges: a search is quicker than a hash
    std::vector<FaceHandle> stack;
    for (size_t j = 0; j < loop.size(); ++j) {
      const VertexHandle p = loop[j], q = loop[(j + 1) % loop.size()];
      own.push_back(EdgeKey(p->info().mesh, q->info().mesh));
      FaceHandle f;
      int e;
      if (!cdt_.is_edge(p, q, f, e))
        return absl::StrCat("an edge of facet ", facets_[i], " was lost in the re-tiling");
      stack.push_back(f->vertex(cdt_.ccw(e)) == p ? f : f->neighbor(e));
    }
    const uint32_t stamp = uint32_t(i) + 1;
    double area = 0;
    while (!stack.empty()) {
      const FaceHandle f = stack.back();
      stack.pop_back();
      if (cdt_.is_infinite(f))
        return absl::StrCat("the inside of facet ", facets_[i], " is not closed in the plane");
      FaceInfo& info = f->info();
      if (info.stamp == stamp) continue;
      info.stamp = stamp;
      if (info.covers == 2) return "a point of the contact lies under three facets";
      info.cover[info.covers++] = uint32_t(i);
      area += CGAL::area(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      for (int e = 0; e < 3; ++e)
        if (std::find(own.begin(), own.end(),
                      EdgeKey(f->vertex(cdt_.ccw(e))->info().mesh,
                              f->vertex(cdt_.cw(e))->info().mesh)) == own.end())
          stack.push_back(f->neighbor(e));
    }
    if (std::fabs(area - expected) > 1e-6 * expected)
      return absl::StrCat("the pieces of facet ", facets_[i], " do not cover it (area ", area,
                          " of ", expected, ")");
  }

  // The faces under one facet keep its side; those under two (facing opposite ways) are the
  // shared contact, written once, facing +k as one of the two does (one way over the contact).
  double centroid[3] = {0, 0, 0};
  for (auto f = cdt_.finite_faces_begin(); f != cdt_.finite_faces_end(); ++f) {
    const FaceInfo& info = f->info();
    if (info.covers == 0) continue;
    uint32_t of = info.cover[0];
    if (info.covers == 2) {
      if (sign[info.cover[0]] == sign[info.cover[1]])
        return absl::StrCat("facets ", facets_[info.cover[0]], " and ", facets_[info.cover[1]],
                            " overlap facing the same way");
      of = sign[info.cover[0]] > 0 ? info.cover[0] : info.cover[1];
      const double a = std::fabs(CGAL::area(f->vertex(0)->point(), f->vertex(1)->point(),
                                            f->vertex(2)->point())) /
                       std::fabs(normal[k_]);
      out.contact.area += a;
      for (int c = 0; c < 3; ++c) {
        const std::array<double, 3> p = [&] {
          const uint32_t v = f->vertex(c)->info().mesh;
          if (v < next_point_ - out.points.size()) return Pos(v);
          const std::array<float, 3>& q = out.points[v - (next_point_ - out.points.size())];
          return std::array<double, 3>{q[0], q[1], q[2]};
        }();
        for (int d = 0; d < 3; ++d) centroid[d] += a * p[d] / 3.0;
      }
      ++out.contact.shared_facets;
    }
    std::array<uint32_t, 3> t = {f->vertex(0)->info().mesh, f->vertex(1)->info().mesh,
                                 f->vertex(2)->info().mesh};
    if (sign[of] < 0) std::swap(t[1], t[2]);
    out.facets.push_back(t);
    out.facet_of.push_back(facets_[of]);
  }
  if (out.contact.shared_facets == 0) return "the facets do not overlap once re-tiled";
  for (int d = 0; d < 3; ++d) out.contact.at[d] = centroid[d] / out.contact.area;

  for (size_t i = 0; i < facets_.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const VertexHandle p = handle[Corner(i, c)], q = handle[Corner(i, (c + 1) % 3)];
      if (p == q) continue;
      const std::vector<VertexHandle> chain = Along(p, q);
      if (chain.size() < 3) continue;
      std::vector<uint32_t> ids;
      for (const VertexHandle& h : chain) ids.push_back(h->info().mesh);
      if (ids.front() > ids.back()) std::reverse(ids.begin(), ids.end());
      out.cut_edges[EdgeKey(ids.front(), ids.back())] = std::move(ids);
    }
  out.contact.first_facet = *std::min_element(facets_.begin(), facets_.end());
  out.contact.facets_before = facets_.size();
  out.contact.facets_after = out.facets.size();
  out.contact.points_added = out.points.size();
  out.contact.corners_merged = out.merged.size();
  return out;
}

// The mesh being imprinted: facets die and are appended within a round, and are compacted after.
class Imprinter {
 public:
  explicit Imprinter(RawMesh& mesh) : mesh_(mesh) {
    facet_origin_.resize(mesh.num_faces());
    std::iota(facet_origin_.begin(), facet_origin_.end(), 0u);
    vertex_origin_.resize(mesh.num_vertices());
    std::iota(vertex_origin_.begin(), vertex_origin_.end(), 0u);
  }

  ImprintResult Run();

 private:
  void Commit(Retiling& r);
  // Splits facet f at the points along its edges that a re-tiling cut (the first piece stays f).
  void SplitAlongCuts(uint32_t f, const absl::flat_hash_map<uint64_t, std::vector<uint32_t>>& cuts);
  uint32_t AppendFacet(const std::array<uint32_t, 3>& t, uint32_t like);
  void Compact();

  RawMesh& mesh_;
  std::vector<uint32_t> facet_origin_, vertex_origin_;
  std::vector<bool> dead_;
  ImprintResult result_;
};

uint32_t Imprinter::AppendFacet(const std::array<uint32_t, 3>& t, uint32_t like) {
  mesh_.triangles.insert(mesh_.triangles.end(), t.begin(), t.end());
  if (!mesh_.face_groups.empty()) mesh_.face_groups.push_back(mesh_.face_groups[like]);
  for (FaceField& field : mesh_.face_fields) field.values.push_back(field.values[like]);
  facet_origin_.push_back(facet_origin_[like]);
  dead_.push_back(false);
  return uint32_t(mesh_.num_faces() - 1);
}

void Imprinter::SplitAlongCuts(uint32_t f,
                               const absl::flat_hash_map<uint64_t, std::vector<uint32_t>>& cuts) {
  std::vector<uint32_t> work = {f};
  while (!work.empty()) {
    const uint32_t g = work.back();
    work.pop_back();
    uint32_t* t = &mesh_.triangles[3 * size_t{g}];
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = t[c], b = t[(c + 1) % 3], apex = t[(c + 2) % 3];
      const auto it = cuts.find(EdgeKey(a, b));
      if (it == cuts.end()) continue;
      std::vector<uint32_t> chain = it->second;
      if (chain.front() != a) std::reverse(chain.begin(), chain.end());
      // (a, m1, apex), (m1, m2, apex), ..., (mk, b, apex): the first stays g.
      const std::array<uint32_t, 3> first = {chain[0], chain[1], apex};
      for (size_t j = 1; j + 1 < chain.size(); ++j)
        work.push_back(AppendFacet({chain[j], chain[j + 1], apex}, g));
      t = &mesh_.triangles[3 * size_t{g}];  // the append may have moved the array
      std::copy(first.begin(), first.end(), t);
      ++result_.neighbours_split;
      work.push_back(g);
      break;
    }
  }
}

void Imprinter::Commit(Retiling& r) {
  if (!r.merged.empty()) {
    absl::flat_hash_map<uint32_t, uint32_t> into(r.merged.begin(), r.merged.end());
    for (uint32_t& v : mesh_.triangles)
      if (const auto it = into.find(v); it != into.end()) v = it->second;
  }
  for (const std::array<float, 3>& p : r.points) {
    mesh_.positions.insert(mesh_.positions.end(), p.begin(), p.end());
    vertex_origin_.push_back(kNoSourceVertex);
  }
  const size_t alive = mesh_.num_faces();
  for (size_t f = 0; f < alive; ++f) {
    if (dead_[f]) continue;
    const uint32_t* t = &mesh_.triangles[3 * f];
    for (int c = 0; c < 3; ++c)
      if (r.cut_edges.contains(EdgeKey(t[c], t[(c + 1) % 3]))) {
        SplitAlongCuts(uint32_t(f), r.cut_edges);
        break;
      }
  }
  for (size_t j = 0; j < r.facets.size(); ++j) AppendFacet(r.facets[j], r.facet_of[j]);
}

void Imprinter::Compact() {
  RawMesh& m = mesh_;
  size_t kept = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    if (dead_[f]) continue;
    std::copy_n(&m.triangles[3 * f], 3, &m.triangles[3 * kept]);
    if (!m.face_groups.empty()) m.face_groups[kept] = m.face_groups[f];
    for (FaceField& field : m.face_fields) field.values[kept] = field.values[f];
    facet_origin_[kept] = facet_origin_[f];
    ++kept;
  }
  m.triangles.resize(3 * kept);
  if (!m.face_groups.empty()) m.face_groups.resize(kept);
  for (FaceField& field : m.face_fields) field.values.resize(kept);
  facet_origin_.resize(kept);
  // Vertices no facet uses any more (corners merged into the other body's) are dropped.
  std::vector<uint32_t> renumber(m.num_vertices(), kNone);
  for (uint32_t v : m.triangles) renumber[v] = 0;
  std::vector<float> positions;
  std::vector<uint32_t> origin;
  for (size_t v = 0; v < renumber.size(); ++v) {
    if (renumber[v] == kNone) continue;
    renumber[v] = uint32_t(origin.size());
    positions.insert(positions.end(), &m.positions[3 * v], &m.positions[3 * v] + 3);
    origin.push_back(vertex_origin_[v]);
  }
  for (uint32_t& v : m.triangles) v = renumber[v];
  m.positions = std::move(positions);
  vertex_origin_ = std::move(origin);
}

ImprintResult Imprinter::Run() {
  std::optional<RawMesh> before;
  uint64_t crossings_before = 0, crossings_now = 0;
  // A round that imprinted something is followed by another: its search for contacts is also
  // the check of the one before (what is left, what crosses).
  for (int round = 0;; ++round) {
    CrossingPairLists lists;
    const SoupCrossings found = FindCrossings(mesh_, {.lists = &lists});
    std::vector<std::pair<uint32_t, uint32_t>>& pairs = lists.overlapping;
    if (round == 0) crossings_before = found.pairs;
    crossings_now = found.pairs;
    if (pairs.empty()) break;
    if (round == kMaxRounds) {
      const float* p = &mesh_.positions[3 * size_t{mesh_.triangles[3 * size_t{pairs[0].first}]}];
      result_.left.push_back({facet_origin_[pairs[0].first],
                              {p[0], p[1], p[2]},
                              absl::StrCat("contacts that meet others were still left after ",
                                           kMaxRounds, " rounds")});
      break;
    }
    if (!before) before = mesh_;
    const double tolerance = ContactPlaneTolerance(mesh_);
    // Contacts: facets joined by their overlaps, each grown over the flat faces of the bodies it
    // lies in (the facets joined to it by an edge in its plane), so that one re-tiling takes in
    // every facet of either body there, also those that overlap another's by less than the
    // overlap test sees.
    UnionFind sets(mesh_.num_faces());
    for (const auto& [a, b] : pairs) sets.Union(a, b);
    std::vector<std::pair<uint64_t, uint32_t>> facets_on;  // (edge, facet), by edge
    facets_on.reserve(mesh_.triangles.size());
    for (size_t f = 0; f < mesh_.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) {
        const uint32_t* t = &mesh_.triangles[3 * f];
        facets_on.emplace_back(EdgeKey(t[c], t[(c + 1) % 3]), uint32_t(f));
      }
    std::sort(facets_on.begin(), facets_on.end());
    std::vector<bool> reached(mesh_.num_faces(), false);
    std::vector<uint32_t> grow;
    for (const auto& [a, b] : pairs)
      for (uint32_t f : {a, b})
        if (!reached[f]) {
          reached[f] = true;
          grow.push_back(f);
        }
    while (!grow.empty()) {
      const uint32_t f = grow.back();
      grow.pop_back();
      const uint32_t* t = &mesh_.triangles[3 * size_t{f}];
      for (int c = 0; c < 3; ++c)
        for (auto it = std::lower_bound(facets_on.begin(), facets_on.end(),
                                        std::pair(EdgeKey(t[c], t[(c + 1) % 3]), uint32_t{0}));
             it != facets_on.end() && it->first == EdgeKey(t[c], t[(c + 1) % 3]); ++it) {
          const uint32_t g = it->second;
          if (g == f || !InOnePlane(mesh_, f, g, tolerance)) continue;
          sets.Union(f, g);
          if (!reached[g]) {
            reached[g] = true;
            grow.push_back(g);
          }
        }
    }
    absl::flat_hash_map<uint32_t, std::vector<uint32_t>> by_root;
    for (size_t f = 0; f < mesh_.num_faces(); ++f)
      if (reached[f]) by_root[sets.Find(uint32_t(f))].push_back(uint32_t(f));
    std::vector<std::vector<uint32_t>> contacts;
    for (auto& [root, facets] : by_root) {
      std::sort(facets.begin(), facets.end());
      facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
      contacts.push_back(std::move(facets));
    }
    std::sort(contacts.begin(), contacts.end());
    dead_.assign(mesh_.num_faces(), false);
    absl::flat_hash_set<uint32_t> touched;  // vertices of the contacts imprinted this round
    bool imprinted = false;
    std::vector<ContactLeft> left;
    for (const std::vector<uint32_t>& facets : contacts) {
      bool meets = false;
      for (uint32_t f : facets)
        for (int c = 0; c < 3; ++c) meets |= touched.contains(mesh_.triangles[3 * size_t{f} + c]);
      if (meets) continue;  // the next round's
      std::variant<Retiling, std::string> r = std::string();
      try {  // CGAL reports a violated precondition by an exception: the contact stays
        r = ContactRetiler(mesh_, facets, tolerance, uint32_t(mesh_.num_vertices())).Run();
      } catch (const std::exception& e) {
        r = absl::StrCat("the triangulation failed: ", e.what());
      }
      if (std::string* why = std::get_if<std::string>(&r)) {
        const float* p = &mesh_.positions[3 * size_t{mesh_.triangles[3 * size_t{facets[0]}]}];
        left.push_back({facet_origin_[facets[0]], {p[0], p[1], p[2]}, std::move(*why)});
        continue;
      }
      Retiling& retiling = std::get<Retiling>(r);
      for (uint32_t f : facets) {
        dead_[f] = true;
        for (int c = 0; c < 3; ++c) touched.insert(mesh_.triangles[3 * size_t{f} + c]);
      }
      for (const auto& [corner, into] : retiling.merged) touched.insert(into);
      retiling.contact.first_facet = facet_origin_[retiling.contact.first_facet];
      Commit(retiling);
      result_.contacts.push_back(retiling.contact);
      imprinted = true;
    }
    if (!imprinted) {  // nothing was deferred: every contact found was tried
      result_.left = std::move(left);
      break;
    }
    Compact();
  }
  if (result_.contacts.empty()) return std::move(result_);
  // A re-tiled contact lies in its plane, so it crosses nothing the bodies did not; should
  // rounding make it, the mesh goes back as it was.
  if (crossings_now > crossings_before) {
    mesh_ = *std::move(before);
    for (const ImprintedContact& c : result_.contacts)
      result_.left.push_back({c.first_facet, c.at, "its re-tiling would cross other facets"});
    result_.contacts.clear();
    result_.neighbours_split = 0;
    return std::move(result_);
  }
  result_.facet_origin = std::move(facet_origin_);
  result_.vertex_origin = std::move(vertex_origin_);
  return std::move(result_);
}

}  // namespace

ImprintResult ImprintContacts(RawMesh& mesh) { return Imprinter(mesh).Run(); }

}  // namespace femsimp
