#include "tests/engine/mesh_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/io/mesh_io.h"

namespace femsimp::testing {
namespace {

uint32_t Find(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

SurfaceTopology Topology(const RawMesh& mesh) {
  SurfaceTopology t;
  const size_t nv = mesh.num_vertices();
  std::vector<uint32_t> parent(nv);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<bool> used(nv, false);
  std::unordered_map<uint64_t, int> edge_uses;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = mesh.triangles[3 * f + i], b = mesh.triangles[3 * f + (i + 1) % 3];
      used[a] = true;
      ++edge_uses[(uint64_t{std::min(a, b)} << 32) | std::max(a, b)];
      parent[Find(parent, a)] = Find(parent, b);
    }
  }
  t.faces = static_cast<long>(mesh.num_faces());
  t.edges = static_cast<long>(edge_uses.size());
  for (const auto& [edge, uses] : edge_uses) t.boundary_edges += uses == 1;
  for (uint32_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    ++t.vertices;
    t.components += Find(parent, v) == v;
  }
  return t;
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

double MinAngleDegrees(const RawMesh& mesh, size_t face) {
  double p[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) p[i][k] = mesh.positions[3 * mesh.triangles[3 * face + i] + k];
  double smallest = 180.0;
  for (int i = 0; i < 3; ++i) {
    double u[3], w[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = p[(i + 1) % 3][k] - p[i][k];
      w[k] = p[(i + 2) % 3][k] - p[i][k];
    }
    const double d = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
    const double nu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const double nw = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    smallest = std::min(smallest,
                        std::acos(std::clamp(d / (nu * nw), -1.0, 1.0)) * 180.0 / std::numbers::pi);
  }
  return smallest;
}

RawMesh LoadTestMesh(const std::string& name) {
  absl::StatusOr<RawMesh> raw = ReadMeshFile(std::string(FEMSIMP_TEST_DATA) + "/" + name);
  EXPECT_TRUE(raw.ok()) << raw.status();
  return raw.ok() ? *std::move(raw) : RawMesh{};
}

}  // namespace femsimp::testing
