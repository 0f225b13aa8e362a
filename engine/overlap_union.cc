#include "engine/overlap_union.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <exception>
#include <memory>
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

// Exact constructions: the points where the surfaces cross are computed exactly and only rounded
// when written back, so the union's own topology never depends on rounding.
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
using FaceIndex = SurfaceMesh::Face_index;
using VertexIndex = SurfaceMesh::Vertex_index;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr const char* kFaceSource = "f:femsimp_source";
constexpr const char* kVertexSource = "v:femsimp_source";

SurfaceMesh::Property_map<FaceIndex, uint32_t> FaceSources(SurfaceMesh& m) {
  return m.add_property_map<FaceIndex, uint32_t>(kFaceSource, kNoUnionSource).first;
}
SurfaceMesh::Property_map<VertexIndex, uint32_t> VertexSources(SurfaceMesh& m) {
  return m.add_property_map<VertexIndex, uint32_t>(kVertexSource, kNoUnionSource).first;
}

// Carries each face's and vertex's source in the mesh given through the corefinement: a face cut
// into pieces passes its source to them, and the union's faces and vertices take their copies'.
// CGAL copies the visitor, so the face being cut is shared state.
struct SourceVisitor : PMP::Corefinement::Default_visitor<SurfaceMesh> {
  std::shared_ptr<uint32_t> cut_source = std::make_shared<uint32_t>(kNoUnionSource);

  void before_subface_creations(FaceIndex f, SurfaceMesh& tm) { *cut_source = FaceSources(tm)[f]; }
  void after_subface_created(FaceIndex f, SurfaceMesh& tm) { FaceSources(tm)[f] = *cut_source; }
  void after_face_copy(FaceIndex from, const SurfaceMesh& tm_from, FaceIndex to,
                       SurfaceMesh& tm_to) {
    FaceSources(tm_to)[to] = tm_from.property_map<FaceIndex, uint32_t>(kFaceSource).first[from];
  }
  void after_vertex_copy(VertexIndex from, const SurfaceMesh& tm_from, VertexIndex to,
                         SurfaceMesh& tm_to) {
    VertexSources(tm_to)[to] =
        tm_from.property_map<VertexIndex, uint32_t>(kVertexSource).first[from];
  }
};

std::array<double, 3> Position(const RawMesh& mesh, uint32_t v) {
  const float* p = &mesh.positions[3 * size_t{v}];
  return {p[0], p[1], p[2]};
}

std::array<double, 3> Centroid(const RawMesh& mesh, uint32_t f) {
  std::array<double, 3> c{};
  for (int k = 0; k < 3; ++k) {
    const std::array<double, 3> p = Position(mesh, mesh.triangles[3 * size_t{f} + k]);
    for (int i = 0; i < 3; ++i) c[i] += p[i] / 3.0;
  }
  return c;
}

uint64_t DirectedKey(uint32_t a, uint32_t b) { return uint64_t{a} << 32 | b; }

// The facets of each component (facets joined through shared vertices), in facet order.
std::vector<std::vector<uint32_t>> Components(const RawMesh& mesh,
                                              std::vector<uint32_t>& component_of) {
  UnionFind vertices(mesh.num_vertices());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    vertices.Union(mesh.triangles[3 * f], mesh.triangles[3 * f + 1]);
    vertices.Union(mesh.triangles[3 * f], mesh.triangles[3 * f + 2]);
  }
  absl::flat_hash_map<uint32_t, uint32_t> index_of_root;
  std::vector<std::vector<uint32_t>> components;
  component_of.assign(mesh.num_faces(), 0);
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t root = vertices.Find(mesh.triangles[3 * f]);
    auto [it, added] = index_of_root.try_emplace(root, static_cast<uint32_t>(components.size()));
    if (added) components.emplace_back();
    components[it->second].push_back(static_cast<uint32_t>(f));
    component_of[f] = it->second;
  }
  return components;
}

// Why the facets are not a body a union takes (empty: they are): each directed edge used once
// and its reverse once, and a positive enclosed volume.
std::string NotABody(const RawMesh& mesh, const std::vector<uint32_t>& facets) {
  absl::flat_hash_set<uint64_t> directed;
  directed.reserve(3 * facets.size());
  double volume6 = 0.0;
  const std::array<double, 3> o = Position(mesh, mesh.triangles[3 * size_t{facets[0]}]);
  for (uint32_t f : facets) {
    const uint32_t* t = &mesh.triangles[3 * size_t{f}];
    for (int k = 0; k < 3; ++k)
      if (!directed.insert(DirectedKey(t[k], t[(k + 1) % 3])).second)
        return "its facets are not consistently oriented";
    std::array<double, 3> p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = Position(mesh, t[k]);
      for (int i = 0; i < 3; ++i) p[k][i] -= o[i];
    }
    volume6 += p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
               p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
               p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
  }
  for (uint64_t key : directed)
    if (!directed.contains(key << 32 | key >> 32)) return "it is not closed";
  if (!(volume6 > 0.0)) return "it faces inward (a cavity's wall) or encloses no volume";
  return "";
}

// The facets as a CGAL surface, each face and vertex knowing its source; none where a vertex's
// facets do not make one fan (CGAL's surfaces are manifold).
std::optional<SurfaceMesh> ToSurfaceMesh(const RawMesh& mesh, const std::vector<uint32_t>& facets) {
  SurfaceMesh sm;
  auto face_source = FaceSources(sm);
  auto vertex_source = VertexSources(sm);
  absl::flat_hash_map<uint32_t, VertexIndex> vertex_of;
  for (uint32_t f : facets) {
    VertexIndex corner[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[3 * size_t{f} + k];
      auto [it, added] = vertex_of.try_emplace(v);
      if (added) {
        const std::array<double, 3> p = Position(mesh, v);
        it->second = sm.add_vertex(K::Point_3(p[0], p[1], p[2]));
        vertex_source[it->second] = v;
      }
      corner[k] = it->second;
    }
    const FaceIndex face = sm.add_face(corner[0], corner[1], corner[2]);
    if (face == SurfaceMesh::null_face()) return std::nullopt;
    face_source[face] = f;
  }
  return sm;
}

struct GroupUnion {
  UnitedBodies record;
  std::vector<uint32_t> members;  // the bodies' facets
  SurfaceMesh surface;
};

struct NoUnion {
  std::string reason;
  bool body_crosses_itself = false;
};

// The union of one group's bodies, or why there is none.
std::variant<GroupUnion, NoUnion> Unite(const RawMesh& mesh,
                                        const std::vector<std::vector<uint32_t>>& components,
                                        const std::vector<uint32_t>& group) {
  GroupUnion u;
  std::optional<SurfaceMesh> acc;
  for (size_t i = 0; i < group.size(); ++i) {
    const std::vector<uint32_t>& facets = components[group[i]];
    u.members.insert(u.members.end(), facets.begin(), facets.end());
    const std::string why = NotABody(mesh, facets);
    if (!why.empty())
      return NoUnion{
          absl::StrCat("the surface of facet ", facets[0], " is not a body a union takes: ", why)};
    std::optional<SurfaceMesh> built = ToSurfaceMesh(mesh, facets);
    if (!built)
      return NoUnion{
          absl::StrCat("the surface of facet ", facets[0], " is not manifold at a vertex")};
    SurfaceMesh body = *std::move(built);
    if (PMP::does_self_intersect(body))
      return NoUnion{absl::StrCat("the surface of facet ", facets[0], " crosses itself"), true};
    u.record.volume_before += CGAL::to_double(PMP::volume(body));
    if (!acc) {
      acc = std::move(body);
      continue;
    }
    SurfaceMesh out;
    FaceSources(out);
    VertexSources(out);
    if (!PMP::corefine_and_compute_union(
            *acc, body, out, CGAL::parameters::visitor(SourceVisitor{}),
            CGAL::parameters::visitor(SourceVisitor{}), CGAL::parameters::all_default()) ||
        !CGAL::is_closed(out))
      return NoUnion{
          "their union is not a closed surface (bodies touching along an edge or at a point)"};
    acc = std::move(out);
  }
  std::sort(u.members.begin(), u.members.end());
  u.record.bodies = group.size();
  u.record.first_facet = u.members.front();
  u.record.facets_before = u.members.size();
  u.record.facets_after = acc->number_of_faces();
  u.record.volume_after = CGAL::to_double(PMP::volume(*acc));
  auto vertex_source = acc->property_map<VertexIndex, uint32_t>(kVertexSource).first;
  for (VertexIndex v : acc->vertices())
    if (vertex_source[v] == kNoUnionSource) ++u.record.points_added;
  u.surface = std::move(*acc);
  return u;
}

// The mesh with the unions of `applied` in place of their bodies, and its provenance.
RawMesh Assemble(const RawMesh& mesh, const std::vector<GroupUnion*>& applied,
                 std::vector<uint32_t>& facet_origin, std::vector<uint32_t>& vertex_origin) {
  std::vector<uint8_t> replaced(mesh.num_faces(), 0);
  for (const GroupUnion* u : applied)
    for (uint32_t f : u->members) replaced[f] = 1;
  facet_origin.clear();
  std::vector<uint32_t> triangles;  // in the mesh given's vertices; kNoUnionSource - i: new point i
  std::vector<std::array<float, 3>> new_points;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (replaced[f]) continue;
    facet_origin.push_back(f);
    triangles.insert(triangles.end(), &mesh.triangles[3 * size_t{f}],
                     &mesh.triangles[3 * size_t{f}] + 3);
  }
  for (const GroupUnion* u : applied) {
    const SurfaceMesh& s = u->surface;
    auto face_source = s.property_map<FaceIndex, uint32_t>(kFaceSource).first;
    auto vertex_source = s.property_map<VertexIndex, uint32_t>(kVertexSource).first;
    absl::flat_hash_map<uint32_t, uint32_t> new_index;  // the surface's vertex -> encoded id
    for (FaceIndex f : s.faces()) {
      facet_origin.push_back(face_source[f]);
      for (VertexIndex v : s.vertices_around_face(s.halfedge(f))) {
        const uint32_t source = vertex_source[v];
        if (source != kNoUnionSource) {
          triangles.push_back(source);
          continue;
        }
        auto [it, added] = new_index.try_emplace(static_cast<uint32_t>(v.idx()));
        if (added) {
          const K::Point_3& p = s.point(v);
          new_points.push_back({static_cast<float>(CGAL::to_double(p.x())),
                                static_cast<float>(CGAL::to_double(p.y())),
                                static_cast<float>(CGAL::to_double(p.z()))});
          it->second = kNoUnionSource - static_cast<uint32_t>(new_points.size());
        }
        triangles.push_back(it->second);
      }
    }
  }
  // Vertices: those still used, in their order, then the new points.
  const uint32_t first_new = kNoUnionSource - static_cast<uint32_t>(new_points.size());
  std::vector<uint32_t> renumber(mesh.num_vertices(), kNoUnionSource);
  for (uint32_t v : triangles)
    if (v < first_new) renumber[v] = 0;
  RawMesh out;
  vertex_origin.clear();
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    if (renumber[v] == kNoUnionSource) continue;
    renumber[v] = static_cast<uint32_t>(vertex_origin.size());
    vertex_origin.push_back(v);
    out.positions.insert(out.positions.end(), &mesh.positions[3 * size_t{v}],
                         &mesh.positions[3 * size_t{v}] + 3);
  }
  const uint32_t kept = static_cast<uint32_t>(vertex_origin.size());
  for (const std::array<float, 3>& p : new_points) {
    vertex_origin.push_back(kNoUnionSource);
    out.positions.insert(out.positions.end(), p.begin(), p.end());
  }
  out.triangles.reserve(triangles.size());
  for (uint32_t v : triangles)
    out.triangles.push_back(v < first_new ? renumber[v] : kept + (kNoUnionSource - v - 1));
  if (!mesh.face_groups.empty())
    for (uint32_t f : facet_origin) out.face_groups.push_back(mesh.face_groups[f]);
  for (const FaceField& field : mesh.face_fields) {
    FaceField carried{field.name, {}};
    carried.values.reserve(facet_origin.size());
    for (uint32_t f : facet_origin) carried.values.push_back(field.values[f]);
    out.face_fields.push_back(std::move(carried));
  }
  out.origin = mesh.origin;
  return out;
}

}  // namespace

UnionResult UniteOverlaps(const RawMesh& mesh) {
  UnionResult result;
  // Seams, locked vertices and parts are made after the repair; a mesh that has them is not one
  // this step is for.
  if (mesh.num_faces() == 0 || !mesh.locked_vertices.empty() || !mesh.point_ids.empty() ||
      !mesh.face_sides.empty())
    return result;
  CrossingPairLists lists;
  CrossingScan scan;
  scan.lists = &lists;
  scan.crossings_only = true;
  scan.stop_after = kEnoughCrossingPairs;
  FindCrossings(mesh, scan);
  if (lists.crossing.empty()) return result;

  std::vector<uint32_t> component_of;
  const std::vector<std::vector<uint32_t>> components = Components(mesh, component_of);
  UnionFind linked(components.size());
  absl::flat_hash_map<uint32_t, uint32_t> crossing_facet;  // component -> a facet where it crosses
  std::sort(lists.crossing.begin(), lists.crossing.end());
  for (const auto& [a, b] : lists.crossing) {
    const uint32_t ca = component_of[a], cb = component_of[b];
    if (ca == cb) continue;  // a surface crossing itself: the crossing repair's
    linked.Union(ca, cb);
    crossing_facet.try_emplace(ca, a);
    crossing_facet.try_emplace(cb, b);
  }
  // Groups: components linked by crossings, in the order of their lowest component.
  absl::flat_hash_map<uint32_t, size_t> group_of_root;
  std::vector<std::vector<uint32_t>> groups;
  for (uint32_t c = 0; c < components.size(); ++c) {
    if (!crossing_facet.contains(c)) continue;
    auto [it, added] = group_of_root.try_emplace(linked.Find(c), groups.size());
    if (added) groups.emplace_back();
    groups[it->second].push_back(c);
  }

  std::vector<GroupUnion> unions;
  unions.reserve(groups.size());
  for (const std::vector<uint32_t>& group : groups) {
    const uint32_t where = crossing_facet.at(group.front());
    std::variant<GroupUnion, NoUnion> u;
    try {
      u = Unite(mesh, components, group);
    } catch (const std::exception& e) {
      u = NoUnion{absl::StrCat("the union failed: ", e.what())};
    }
    if (NoUnion* no = std::get_if<NoUnion>(&u)) {
      result.left.push_back({components[group.front()].front(), Centroid(mesh, where),
                             std::move(no->reason), no->body_crosses_itself});
      continue;
    }
    unions.push_back(std::get<GroupUnion>(std::move(u)));
    unions.back().record.at = Centroid(mesh, where);
  }
  if (unions.empty()) return result;

  // The new points are rounded to floats: a union whose facets then cross is left as it was.
  std::vector<GroupUnion*> applied;
  for (GroupUnion& u : unions) applied.push_back(&u);
  RawMesh united = Assemble(mesh, applied, result.facet_origin, result.vertex_origin);
  CrossingPairLists after;
  scan.lists = &after;
  FindCrossings(united, scan);
  absl::flat_hash_set<uint32_t> spoiled;  // first facets of the unions whose facets cross
  std::vector<uint32_t> union_of_facet(mesh.num_faces(), kNoUnionSource);
  for (size_t i = 0; i < unions.size(); ++i)
    for (uint32_t f : unions[i].members) union_of_facet[f] = static_cast<uint32_t>(i);
  const size_t kept_facets = united.num_faces() - [&] {
    size_t n = 0;
    for (const GroupUnion& u : unions) n += u.record.facets_after;
    return n;
  }();
  for (const auto& [a, b] : after.crossing)
    for (uint32_t f : {a, b})
      if (f >= kept_facets) spoiled.insert(union_of_facet[result.facet_origin[f]]);
  if (!spoiled.empty()) {
    applied.clear();
    for (size_t i = 0; i < unions.size(); ++i) {
      if (!spoiled.contains(static_cast<uint32_t>(i))) {
        applied.push_back(&unions[i]);
        continue;
      }
      result.left.push_back({unions[i].record.first_facet, unions[i].record.at,
                             "rounding the points where the surfaces cross to float coordinates "
                             "makes facets of the union cross"});
    }
    if (applied.empty()) {
      result.facet_origin.clear();
      result.vertex_origin.clear();
      return result;
    }
    united = Assemble(mesh, applied, result.facet_origin, result.vertex_origin);
  }
  for (const GroupUnion* u : applied) result.united.push_back(u->record);
  result.mesh = std::move(united);
  return result;
}

}  // namespace femsimp
