#include "engine/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"

namespace femsimp {
namespace {

uint32_t Root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Twice the area of triangle abc and its longest edge squared, in double precision.
void AreaAndLongestEdge(const float* a, const float* b, const float* c, double* twice_area,
                        double* longest2) {
  double u[3], w[3], e[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = double(b[i]) - a[i];
    w[i] = double(c[i]) - a[i];
    e[i] = double(c[i]) - b[i];
  }
  const double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2],
               cz = u[0] * w[1] - u[1] * w[0];
  auto len2 = [](const double* v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; };
  *longest2 = std::max({len2(u), len2(w), len2(e)});
  *twice_area = std::sqrt(cx * cx + cy * cy + cz * cz);
}

}  // namespace

bool IsZeroArea(const float* a, const float* b, const float* c) {
  double twice_area, longest2;
  AreaAndLongestEdge(a, b, c, &twice_area, &longest2);
  // Twice the area against the longest edge squared: a relative test, scale-free.
  return !(twice_area > 1e-12 * longest2);
}

double HeightOverLongestEdge(const float* a, const float* b, const float* c) {
  double twice_area, longest2;
  AreaAndLongestEdge(a, b, c, &twice_area, &longest2);
  return longest2 > 0 ? twice_area / std::sqrt(longest2) : 0.0;
}

absl::Status CheckSoup(const RawMesh& raw) {
  if (raw.positions.size() % 3 != 0)
    return absl::InvalidArgumentError(
        absl::StrCat("vertex coordinates: ", raw.positions.size(), " is not a multiple of 3"));
  if (raw.triangles.size() % 3 != 0)
    return absl::InvalidArgumentError(
        absl::StrCat("triangle indices: ", raw.triangles.size(), " is not a multiple of 3"));
  const size_t nv = raw.num_vertices(), nf = raw.num_faces();
  if (nv == 0 || nf == 0)
    return absl::InvalidArgumentError(
        absl::StrCat("mesh is empty (", nv, " vertices, ", nf, " faces)"));
  if (!raw.face_groups.empty() && raw.face_groups.size() != nf)
    return absl::InvalidArgumentError(
        absl::StrCat("face groups: ", raw.face_groups.size(), " ids for ", nf, " faces"));
  if (raw.face_fields.size() > kMaxFaceFields)
    return absl::InvalidArgumentError(
        absl::StrCat("face fields: ", raw.face_fields.size(), " given, at most ", kMaxFaceFields));
  for (size_t i = 0; i < raw.face_fields.size(); ++i) {
    const FaceField& field = raw.face_fields[i];
    if (field.name.empty())
      return absl::InvalidArgumentError(absl::StrCat("face field ", i, " has no name"));
    for (size_t j = 0; j < i; ++j)
      if (raw.face_fields[j].name == field.name)
        return absl::InvalidArgumentError(
            absl::StrCat("face field '", field.name, "' is given twice"));
    if (field.values.size() != nf)
      return absl::InvalidArgumentError(absl::StrCat(
          "face field '", field.name, "': ", field.values.size(), " values for ", nf, " faces"));
    for (size_t f = 0; f < nf; ++f)
      if (!std::isfinite(field.values[f]))
        return absl::InvalidArgumentError(
            absl::StrCat("face field '", field.name, "': face ", f, " has a non-finite value"));
  }
  // Indices are 32-bit and kNone is reserved.
  if (nv >= kNone || 3 * nf >= kNone)
    return absl::InvalidArgumentError(
        absl::StrCat("mesh too large: ", nv, " vertices, ", nf, " faces"));
  for (size_t v = 0; v < nv; ++v) {
    const float* p = &raw.positions[3 * v];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      return absl::InvalidArgumentError(absl::StrCat("vertex ", v, " has a non-finite coordinate (",
                                                     p[0], ", ", p[1], ", ", p[2], ")"));
  }
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &raw.triangles[3 * f];
    for (int i = 0; i < 3; ++i)
      if (t[i] >= nv)
        return absl::InvalidArgumentError(absl::StrCat("face ", f, " references vertex ", t[i],
                                                       " but the mesh has ", nv, " vertices"));
    if (RepeatsVertex(t))
      return absl::InvalidArgumentError(absl::StrCat("face ", f, " is degenerate: vertices (", t[0],
                                                     ", ", t[1], ", ", t[2], ") repeat an index"));
    if (IsZeroArea(&raw.positions[3 * t[0]], &raw.positions[3 * t[1]], &raw.positions[3 * t[2]]))
      return absl::InvalidArgumentError(
          absl::StrCat("face ", f, " (", t[0], ", ", t[1], ", ", t[2], ") has zero area"));
  }
  return absl::OkStatus();
}

SoupTopology TopologyOf(const RawMesh& mesh) {
  SoupTopology t;
  const size_t nf = mesh.num_faces();
  t.faces = static_cast<int64_t>(nf);
  std::vector<bool> used(mesh.num_vertices(), false);
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(3 * nf);
  std::vector<uint32_t> parent(mesh.num_vertices());
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      uint32_t a = mesh.triangles[3 * f + k], b = mesh.triangles[3 * f + (k + 1) % 3];
      if (a >= used.size() || b >= used.size()) continue;  // CheckOutput's Build reports it
      used[a] = true;
      edges.emplace_back(std::min(a, b), std::max(a, b));
      parent[Root(parent, a)] = Root(parent, b);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ++t.edges;
    if (j - i == 1) ++t.boundary_edges;
    i = j;
  }
  for (uint32_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    ++t.vertices;
    if (Root(parent, v) == v) ++t.components;
  }
  return t;
}

absl::Status CheckOutput(const SoupTopology& input, const RawMesh& output) {
  if (absl::StatusOr<Mesh> m = Mesh::Build(output); !m.ok())
    return absl::DataLossError(absl::StrCat("output is not a valid mesh: ", m.status().message()));
  const SoupTopology out = TopologyOf(output);
  if (out.vertices > input.vertices || out.faces > input.faces)
    return absl::DataLossError(absl::StrCat("output (", out.vertices, " vertices, ", out.faces,
                                            " faces) is larger than the input (", input.vertices,
                                            " vertices, ", input.faces, " faces)"));
  if (out.euler() != input.euler())
    return absl::DataLossError(
        absl::StrCat("Euler characteristic changed from ", input.euler(), " to ", out.euler()));
  if (out.components != input.components)
    return absl::DataLossError(
        absl::StrCat("components changed from ", input.components, " to ", out.components));
  if ((out.boundary_edges == 0) != (input.boundary_edges == 0))
    return absl::DataLossError(absl::StrCat("boundary edges went from ", input.boundary_edges,
                                            " to ", out.boundary_edges,
                                            " (closed must stay closed, open stay open)"));
  return absl::OkStatus();
}

std::string HalfEdgeInvariantViolation(const Mesh& mesh) {
  const HalfEdgeQ* he = mesh.halfedges();
  const VertexQ* vx = mesh.vertices();
  std::vector<bool> used(mesh.vertex_capacity(), false);
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (mesh.IsFaceRemoved(f)) continue;
    for (uint32_t h = 3 * f; h < 3 * f + 3; ++h) {
      if (he[h].flags & kFaceRemoved) return absl::StrCat("face ", f, " partly removed");
      if (mesh.IsRemoved(he[h].target))
        return absl::StrCat("half-edge ", h, " points to removed vertex ", he[h].target);
      used[he[h].target] = true;
      const uint32_t t = he[h].twin;
      if (t == kNone) continue;
      if (mesh.IsFaceRemoved(FaceOf(t))) return absl::StrCat("twin of ", h, " is removed");
      if (he[t].twin != h) return absl::StrCat("twins of ", h, " and ", t, " not mutual");
      if (he[t].target != he[Prev(h)].target || he[Prev(t)].target != he[h].target)
        return absl::StrCat("twins ", h, " and ", t, " do not join the same vertices");
    }
  }
  for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v) {
    if (mesh.IsRemoved(v)) continue;
    if (!used[v]) return absl::StrCat("live vertex ", v, " is in no face");
    const uint32_t out = vx[v].out;
    if (out == kNone || mesh.IsFaceRemoved(FaceOf(out)) || he[Prev(out)].target != v)
      return absl::StrCat("vertex ", v, " has an invalid outgoing half-edge");
    // On a boundary vertex the outgoing half-edge must be the one without twin.
    bool boundary = false;
    uint32_t h = out;
    for (int steps = 0; steps < 1000; ++steps) {
      const uint32_t next = he[Prev(h)].twin;
      if (next == kNone) {
        boundary = true;
        break;
      }
      if (next == out) break;
      h = next;
    }
    if (boundary && he[out].twin != kNone)
      return absl::StrCat("boundary vertex ", v, " does not start its fan at the boundary");
  }
  return "";
}

}  // namespace femsimp
