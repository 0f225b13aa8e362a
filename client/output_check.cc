#include "client/output_check.h"

#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/mesh.h"

namespace femsimp::cli {
namespace {

uint32_t Root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

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

}  // namespace femsimp::cli
