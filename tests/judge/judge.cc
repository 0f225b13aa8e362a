#include "tests/judge/judge.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <set>
#include <unordered_map>
#include <utility>

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

namespace femsimp::judge {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

Vec3 Position(const RawMesh& m, uint32_t v) {
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}
Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double Norm(const Vec3& a) { return std::sqrt(Dot(a, a)); }
Point ToPoint(const Vec3& p) { return {p[0], p[1], p[2]}; }

// Twice the area vector of face f (counter-clockwise normal).
Vec3 AreaVector2(const RawMesh& m, size_t f) {
  const Vec3 a = Position(m, m.triangles[3 * f]), b = Position(m, m.triangles[3 * f + 1]),
             c = Position(m, m.triangles[3 * f + 2]);
  return Cross(Sub(b, a), Sub(c, a));
}

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  return (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

uint32_t Find(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}
void Unite(std::vector<uint32_t>& parent, uint32_t a, uint32_t b) {
  parent[Find(parent, a)] = Find(parent, b);
}

// CGAL's algorithms want a halfedge mesh; orienting the soup first duplicates non-manifold
// vertices and flips faces as needed, so any soup converts (neither changes the point set).
SurfaceMesh ToSurfaceMesh(const RawMesh& mesh) {
  std::vector<Point> points;
  points.reserve(mesh.num_vertices());
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) points.push_back(ToPoint(Position(mesh, v)));
  std::vector<std::array<size_t, 3>> faces(mesh.num_faces());
  for (size_t f = 0; f < faces.size(); ++f)
    faces[f] = {mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]};
  PMP::orient_polygon_soup(points, faces);
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, faces, sm);
  return sm;
}

double OneSided(const SurfaceMesh& from, const SurfaceMesh& to, double error) {
  if (from.number_of_faces() == 0) return 0.0;
  if (to.number_of_faces() == 0) return std::numeric_limits<double>::infinity();
  return PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(from, to, error);
}

RawMesh GroupSubmesh(const RawMesh& m, uint32_t group) {
  RawMesh sub;
  std::unordered_map<uint32_t, uint32_t> index;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    if (m.face_groups.empty() ? group != 0 : m.face_groups[f] != group) continue;
    for (int i = 0; i < 3; ++i) {
      const uint32_t v = m.triangles[3 * f + i];
      auto [it, fresh] = index.try_emplace(v, static_cast<uint32_t>(sub.num_vertices()));
      if (fresh)
        sub.positions.insert(sub.positions.end(), m.positions.begin() + 3 * v,
                             m.positions.begin() + 3 * v + 3);
      sub.triangles.push_back(it->second);
    }
  }
  return sub;
}

// Edge -> the faces using it, in the order of the soup.
std::unordered_map<uint64_t, std::vector<uint32_t>> EdgeFaces(const RawMesh& m) {
  std::unordered_map<uint64_t, std::vector<uint32_t>> edges;
  edges.reserve(m.triangles.size());
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    for (int i = 0; i < 3; ++i)
      edges[EdgeKey(m.triangles[3 * f + i], m.triangles[3 * f + (i + 1) % 3])].push_back(f);
  return edges;
}

// Local index (0..2) of vertex v in face f, or -1.
int Corner(const RawMesh& m, uint32_t f, uint32_t v) {
  for (int i = 0; i < 3; ++i)
    if (m.triangles[3 * f + i] == v) return i;
  return -1;
}

// True when face f traverses the edge from a to b.
bool Traverses(const RawMesh& m, uint32_t f, uint32_t a, uint32_t b) {
  const int i = Corner(m, f, a);
  return i >= 0 && m.triangles[3 * f + (i + 1) % 3] == b;
}

using SegmentPrimitive = CGAL::AABB_segment_primitive<K, std::vector<K::Segment_3>::const_iterator>;
using SegmentTree = CGAL::AABB_tree<CGAL::AABB_traits<K, SegmentPrimitive>>;

// Largest distance of points sampled along `from` (at most spacing apart) to the segments of
// `to`; the worst sample goes to *worst.
double SegmentsDistance(const std::vector<Segment>& from, const std::vector<Segment>& to,
                        double spacing, size_t* samples, Vec3* worst) {
  if (from.empty()) return 0.0;
  if (to.empty()) return std::numeric_limits<double>::infinity();
  std::vector<K::Segment_3> segments;
  segments.reserve(to.size());
  for (const Segment& s : to) segments.emplace_back(ToPoint(s.a), ToPoint(s.b));
  SegmentTree tree(segments.begin(), segments.end());
  tree.accelerate_distance_queries();
  double worst_sq = 0.0;
  for (const Segment& s : from) {
    const Vec3 d = Sub(s.b, s.a);
    const int n = std::max(1, static_cast<int>(std::ceil(Norm(d) / spacing)));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      const Vec3 p{s.a[0] + t * d[0], s.a[1] + t * d[1], s.a[2] + t * d[2]};
      const double sq = CGAL::to_double(tree.squared_distance(ToPoint(p)));
      if (samples) ++*samples;
      if (sq > worst_sq) {
        worst_sq = sq;
        if (worst) *worst = p;
      }
    }
  }
  return std::sqrt(worst_sq);
}

}  // namespace

double BoundingBoxDiagonal(const RawMesh& mesh) {
  if (mesh.positions.empty()) return 0.0;
  Vec3 lo, hi;
  lo.fill(std::numeric_limits<double>::max());
  hi.fill(std::numeric_limits<double>::lowest());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    lo[i % 3] = std::min<double>(lo[i % 3], mesh.positions[i]);
    hi[i % 3] = std::max<double>(hi[i % 3], mesh.positions[i]);
  }
  return Norm(Sub(hi, lo));
}

double FloatStorageSlack(const RawMesh& mesh) {
  double largest = 0.0;
  for (float x : mesh.positions) largest = std::max(largest, std::abs(double{x}));
  // Rounding a computed position to float moves each coordinate by half an ulp at most.
  return 4.0 * FLT_EPSILON * largest;
}

Hausdorff HausdorffDistance(const RawMesh& a, const RawMesh& b, double error) {
  const auto start = std::chrono::steady_clock::now();
  const SurfaceMesh sa = ToSurfaceMesh(a), sb = ToSurfaceMesh(b);
  Hausdorff h;
  h.error = error;
  h.a_to_b = OneSided(sa, sb, error);
  h.b_to_a = OneSided(sb, sa, error);
  h.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return h;
}

double SampledHausdorff(const RawMesh& from, const RawMesh& to, double spacing) {
  // Every face is cut into n*n congruent triangles whose sides are at most `spacing`, and all
  // their corners are samples: any point of the face is within spacing / sqrt(3) of one.
  std::vector<Point> samples;
  for (size_t f = 0; f < from.num_faces(); ++f) {
    const Vec3 p0 = Position(from, from.triangles[3 * f]),
               p1 = Position(from, from.triangles[3 * f + 1]),
               p2 = Position(from, from.triangles[3 * f + 2]);
    const double longest = std::max({Norm(Sub(p1, p0)), Norm(Sub(p2, p0)), Norm(Sub(p2, p1))});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double c1 = double(i) / n, c2 = double(j) / n, c0 = 1.0 - c1 - c2;
        samples.emplace_back(c0 * p0[0] + c1 * p1[0] + c2 * p2[0],
                             c0 * p0[1] + c1 * p1[1] + c2 * p2[1],
                             c0 * p0[2] + c1 * p1[2] + c2 * p2[2]);
      }
  }
  if (samples.empty()) return 0.0;
  const SurfaceMesh target = ToSurfaceMesh(to);
  if (target.number_of_faces() == 0) return std::numeric_limits<double>::infinity();
  return PMP::max_distance_to_triangle_mesh<CGAL::Sequential_tag>(samples, target);
}

std::map<uint32_t, Hausdorff> GroupHausdorffDistances(const RawMesh& a, const RawMesh& b,
                                                      double error) {
  std::set<uint32_t> groups;
  for (uint32_t g : GroupIds(a)) groups.insert(g);
  for (uint32_t g : GroupIds(b)) groups.insert(g);
  if (groups.empty()) groups.insert(0);
  std::map<uint32_t, Hausdorff> out;
  for (uint32_t g : groups)
    out[g] = HausdorffDistance(GroupSubmesh(a, g), GroupSubmesh(b, g), error);
  return out;
}

bool SelfIntersects(const RawMesh& mesh) { return PMP::does_self_intersect(ToSurfaceMesh(mesh)); }

size_t SelfIntersectingPairs(const RawMesh& mesh) {
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  PMP::self_intersections(ToSurfaceMesh(mesh), std::back_inserter(pairs));
  return pairs.size();
}

Topology ComputeTopology(const RawMesh& m) {
  Topology t;
  const uint32_t nv = static_cast<uint32_t>(m.num_vertices());
  const uint32_t nf = static_cast<uint32_t>(m.num_faces());
  std::vector<uint32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<bool> used(nv, false);
  for (uint32_t f = 0; f < nf; ++f)
    for (int i = 0; i < 3; ++i) {
      used[m.triangles[3 * f + i]] = true;
      Unite(parent, m.triangles[3 * f + i], m.triangles[3 * f + (i + 1) % 3]);
    }
  const auto edges = EdgeFaces(m);
  t.faces = nf;
  t.edges = static_cast<long>(edges.size());
  // Fans: the corners of a vertex joined across its manifold edges; more than one fan at a
  // vertex makes it non-manifold (two cones touching at their tips, say).
  std::vector<uint32_t> corner(3 * nf);
  std::iota(corner.begin(), corner.end(), 0u);
  std::vector<uint32_t> boundary(nv);
  std::iota(boundary.begin(), boundary.end(), 0u);
  std::vector<bool> on_boundary(nv, false);
  for (const auto& [key, faces] : edges) {
    const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
    if (faces.size() == 1) {
      ++t.boundary_edges;
      on_boundary[a] = on_boundary[b] = true;
      Unite(boundary, a, b);
    } else if (faces.size() > 2) {
      ++t.nonmanifold_edges;
    } else {
      const uint32_t f = faces[0], g = faces[1];
      if (Traverses(m, f, a, b) == Traverses(m, g, a, b)) ++t.misoriented_edges;
      Unite(corner, 3 * f + Corner(m, f, a), 3 * g + Corner(m, g, a));
      Unite(corner, 3 * f + Corner(m, f, b), 3 * g + Corner(m, g, b));
    }
  }
  std::vector<uint32_t> fan_of(nv, UINT32_MAX);
  std::vector<bool> nonmanifold(nv, false);
  for (uint32_t c = 0; c < 3 * nf; ++c) {
    const uint32_t v = m.triangles[c], root = Find(corner, c);
    if (fan_of[v] == UINT32_MAX)
      fan_of[v] = root;
    else if (fan_of[v] != root)
      nonmanifold[v] = true;
  }
  for (uint32_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    ++t.vertices;
    t.components += Find(parent, v) == v;
    t.nonmanifold_vertices += nonmanifold[v];
    t.boundary_loops += on_boundary[v] && Find(boundary, v) == v;
  }
  return t;
}

Solid SolidProperties(const RawMesh& m) {
  Solid s;
  Vec3 moment{};
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const Vec3 a = Position(m, m.triangles[3 * f]), b = Position(m, m.triangles[3 * f + 1]),
               c = Position(m, m.triangles[3 * f + 2]);
    // Signed volume of the tetrahedron (origin, a, b, c); its centroid is (a + b + c) / 4.
    const double v = Dot(a, Cross(b, c)) / 6.0;
    s.volume += v;
    for (int k = 0; k < 3; ++k) moment[k] += v * (a[k] + b[k] + c[k]) / 4.0;
  }
  if (s.volume != 0.0)
    for (int k = 0; k < 3; ++k) s.centroid[k] = moment[k] / s.volume;
  return s;
}

Surface SurfaceProperties(const RawMesh& m) {
  Surface s;
  Vec3 moment{};
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const double area = Norm(AreaVector2(m, f)) / 2.0;
    s.area += area;
    for (int i = 0; i < 3; ++i) {
      const Vec3 p = Position(m, m.triangles[3 * f + i]);
      for (int k = 0; k < 3; ++k) moment[k] += area * p[k] / 3.0;
    }
  }
  if (s.area > 0.0)
    for (int k = 0; k < 3; ++k) s.centroid[k] = moment[k] / s.area;
  return s;
}

std::map<uint32_t, GroupLoad> FieldResultants(const RawMesh& m, size_t field) {
  std::map<uint32_t, GroupLoad> loads;
  const std::vector<float>& p = m.face_fields.at(field).values;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    GroupLoad& g = loads[m.face_groups.empty() ? 0 : m.face_groups[f]];
    const Vec3 n2 = AreaVector2(m, f);
    const double area = Norm(n2) / 2.0;
    for (int k = 0; k < 3; ++k) g.force[k] += p[f] * n2[k] / 2.0;
    g.abs_load += std::abs(double{p[f]}) * area;
    g.area += area;
    ++g.faces;
  }
  return loads;
}

std::map<uint32_t, double> RelativeResultantChange(const std::map<uint32_t, GroupLoad>& a,
                                                   const std::map<uint32_t, GroupLoad>& b) {
  std::map<uint32_t, double> change;
  for (const auto& [group, load] : a) {
    auto it = b.find(group);
    const double diff = it == b.end() ? std::numeric_limits<double>::infinity()
                                      : Norm(Sub(it->second.force, load.force));
    // An unloaded group must stay unloaded.
    change[group] = load.abs_load > 0.0 ? diff / load.abs_load
                    : diff == 0.0       ? 0.0
                                        : std::numeric_limits<double>::infinity();
  }
  return change;
}

FeatureEdges ExtractFeatureEdges(const RawMesh& m, double angle_deg) {
  FeatureEdges out;
  const double cos_limit = std::cos(angle_deg * std::numbers::pi / 180.0);
  for (const auto& [key, faces] : EdgeFaces(m)) {
    const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
    bool feature = false;
    if (faces.size() == 1) {
      ++out.boundary;
      feature = true;
    } else if (faces.size() > 2) {
      ++out.nonmanifold;
      feature = true;
    } else {
      if (!m.face_groups.empty() && m.face_groups[faces[0]] != m.face_groups[faces[1]]) {
        ++out.group_border;
        feature = true;
      }
      const Vec3 n0 = AreaVector2(m, faces[0]), n1 = AreaVector2(m, faces[1]);
      const double l0 = Norm(n0), l1 = Norm(n1);
      // The angle between the normals of oriented neighbours, as the options mean it: 0 on a
      // flat surface, 90 on a cube's edge.
      if (l0 > 0.0 && l1 > 0.0 && Dot(n0, n1) / (l0 * l1) < cos_limit) {
        ++out.sharp;
        feature = true;
      }
    }
    if (feature) out.segments.push_back({Position(m, a), Position(m, b)});
  }
  return out;
}

FeatureCoverage CheckFeatureCoverage(const RawMesh& original, const RawMesh& simplified,
                                     double angle_deg, double spacing,
                                     double simplified_angle_deg) {
  FeatureCoverage c;
  const FeatureEdges from = ExtractFeatureEdges(original, angle_deg);
  const FeatureEdges to = ExtractFeatureEdges(
      simplified, simplified_angle_deg < 0.0 ? angle_deg : simplified_angle_deg);
  c.original_edges = from.segments.size();
  c.simplified_edges = to.segments.size();
  c.error = spacing / 2.0;
  c.max_distance =
      SegmentsDistance(from.segments, to.segments, spacing, &c.samples, &c.worst_point);
  c.reverse_max_distance = SegmentsDistance(to.segments, from.segments, spacing, nullptr, nullptr);
  return c;
}

std::vector<uint32_t> GroupIds(const RawMesh& mesh) {
  const std::set<uint32_t> ids(mesh.face_groups.begin(), mesh.face_groups.end());
  return {ids.begin(), ids.end()};
}

}  // namespace femsimp::judge
