#include "engine/seams.h"

#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "engine/edge_groups.h"
#include "engine/union_find.h"

namespace femsimp {
namespace {

constexpr uint32_t kNoIndex = std::numeric_limits<uint32_t>::max();

// Two faces in opposite directions: the only edges across which faces stay adjacent.
bool IsManifold(const std::vector<uint32_t>& tri, const EdgeGroups& edges, size_t g) {
  if (edges.count(g) != 2) return false;
  return tri[edges.half[edges.begin[g]]] != tri[edges.half[edges.begin[g] + 1]];
}

EdgeUse UseOf(const std::vector<uint32_t>& tri, const EdgeGroups& edges, size_t g) {
  const uint32_t h = edges.half[edges.begin[g]];
  const uint32_t a = tri[h], b = tri[NextCorner(h)];
  return {std::min(a, b), std::max(a, b), edges.count(g)};
}

absl::Status CheckArrays(const RawMesh& mesh) {
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0)
    return absl::InvalidArgumentError("seams: coordinate or index count not a multiple of 3");
  if (nv >= kNoIndex / 2 || mesh.triangles.size() >= kNoIndex)
    return absl::InvalidArgumentError(absl::StrCat("seams: mesh too large (", nv, " vertices)"));
  for (size_t c = 0; c < mesh.triangles.size(); ++c)
    if (mesh.triangles[c] >= nv)
      return absl::InvalidArgumentError(absl::StrCat("seams: face ", c / 3, " references vertex ",
                                                     mesh.triangles[c], " of ", nv));
  for (uint32_t v : mesh.locked_vertices)
    if (v >= nv)
      return absl::InvalidArgumentError(absl::StrCat("seams: locked vertex ", v, " of ", nv));
  if (!mesh.face_groups.empty() && mesh.face_groups.size() != nf)
    return absl::InvalidArgumentError("seams: face groups do not match the faces");
  return absl::OkStatus();
}

}  // namespace

std::vector<EdgeUse> NonManifoldEdges(const RawMesh& mesh) {
  const EdgeGroups edges(mesh.triangles);
  std::vector<EdgeUse> out;
  for (size_t g = 0; g < edges.size(); ++g)
    if (edges.count(g) >= 2 && !IsManifold(mesh.triangles, edges, g))
      out.push_back(UseOf(mesh.triangles, edges, g));
  return out;  // groups are ordered by (low, high)
}

absl::StatusOr<SeamMap> SplitSeams(RawMesh& mesh, const EdgeGroups* grouped) {
  if (absl::Status s = CheckArrays(mesh); !s.ok()) return s;
  const uint32_t nv = static_cast<uint32_t>(mesh.num_vertices());
  const uint32_t nc = static_cast<uint32_t>(mesh.triangles.size());
  std::vector<uint32_t>& tri = mesh.triangles;
  SeamMap map;
  map.input_vertices = nv;

  // Corners at one vertex are in one fan when their faces are adjacent across a manifold edge
  // at that vertex.
  std::optional<EdgeGroups> own;
  const EdgeGroups& edges = grouped != nullptr ? *grouped : own.emplace(tri);
  UnionFind fans(nc);
  std::vector<uint8_t> on_seam(nv, 0);
  for (size_t g = 0; g < edges.size(); ++g) {
    if (IsManifold(tri, edges, g)) {
      const uint32_t h = edges.half[edges.begin[g]], k = edges.half[edges.begin[g] + 1];
      // h runs a -> b, k runs b -> a: corner h and the corner after k are at a, and so on.
      fans.Union(h, NextCorner(k));
      fans.Union(NextCorner(h), k);
    } else if (edges.count(g) >= 2) {
      const EdgeUse use = UseOf(tri, edges, g);
      map.seams.push_back(use);
      on_seam[use.a] = on_seam[use.b] = 1;
    }
  }

  // The first fan of each vertex (by its lowest corner) keeps the vertex; the others get copies.
  std::vector<uint32_t> vertex_of_fan(nc, kNoIndex);
  std::vector<uint8_t> has_fan(nv, 0);
  map.original.resize(nv);
  for (uint32_t v = 0; v < nv; ++v) map.original[v] = v;
  std::vector<uint32_t> new_tri(tri);
  for (uint32_t c = 0; c < nc; ++c) {
    const uint32_t v = tri[c], r = fans.Find(c);
    if (vertex_of_fan[r] == kNoIndex) {
      if (!has_fan[v]) {
        has_fan[v] = 1;
        vertex_of_fan[r] = v;
      } else {
        vertex_of_fan[r] = static_cast<uint32_t>(map.original.size());
        map.original.push_back(v);
        if (has_fan[v] == 1) ++map.split_vertices;
        has_fan[v] = 2;
        on_seam[v] = 1;
      }
    }
    new_tri[c] = vertex_of_fan[r];
  }
  map.copies = map.original.size() - nv;
  if (map.seams.empty() && map.copies == 0) {  // manifold: leave it as it was
    map.original.clear();
    return map;
  }
  tri = std::move(new_tri);

  std::vector<uint8_t> locked(nv, 0);
  for (uint32_t v : mesh.locked_vertices) locked[v] = 1;
  mesh.positions.reserve(3 * map.original.size());
  for (size_t w = nv; w < map.original.size(); ++w)
    for (int k = 0; k < 3; ++k) mesh.positions.push_back(mesh.positions[3 * map.original[w] + k]);
  mesh.point_ids = map.original;
  mesh.locked_vertices.clear();
  for (uint32_t w = 0; w < map.original.size(); ++w) {
    const uint32_t v = map.original[w];
    if (on_seam[v]) map.seam_vertices.push_back(w);
    if (on_seam[v] || locked[v]) mesh.locked_vertices.push_back(w);
  }
  return map;
}

namespace {

bool ByEnds(const EdgeUse& x, const EdgeUse& y) {
  return std::pair(x.a, x.b) < std::pair(y.a, y.b);
}

// The input's seams once the seam vertices without an output copy (first_copy kNoIndex) are left
// out: a chain a - r1 - ... - rk - b through such vertices, each an inner point of one seam
// curve (two seam edges, the same face count), becomes the edge a-b. Any other seam vertex
// without a copy is counted in *missing (once per input vertex).
std::vector<EdgeUse> SeamsWithout(const SeamMap& map, const std::vector<uint32_t>& first_copy,
                                  size_t* missing) {
  const auto kept = [&](uint32_t v) { return first_copy[v] != kNoIndex; };
  absl::flat_hash_map<uint32_t, std::vector<uint32_t>> seam_edges_at;  // vertex -> seams index
  for (uint32_t k = 0; k < map.seams.size(); ++k) {
    seam_edges_at[map.seams[k].a].push_back(k);
    seam_edges_at[map.seams[k].b].push_back(k);
  }
  const auto inner = [&](uint32_t v) {
    const auto it = seam_edges_at.find(v);
    if (it == seam_edges_at.end() || it->second.size() != 2) return false;
    return map.seams[it->second[0]].faces == map.seams[it->second[1]].faces;
  };
  std::vector<uint8_t> counted(map.input_vertices, 0);
  for (uint32_t w : map.seam_vertices) {
    const uint32_t v = map.original[w];
    if (!kept(v) && !inner(v) && !counted[v]) {
      counted[v] = 1;
      ++*missing;
    }
  }
  std::vector<EdgeUse> expected;
  for (const EdgeUse& e : map.seams) {
    // Walk from each kept end through the left-out inner points to the next kept vertex.
    for (const auto& [from, first] : {std::pair(e.a, e.b), std::pair(e.b, e.a)}) {
      if (!kept(from)) continue;
      uint32_t prev = from, at = first;
      size_t steps = 0;
      while (!kept(at) && inner(at) && steps++ <= map.seams.size()) {
        const std::vector<uint32_t>& two = seam_edges_at[at];
        const EdgeUse& next = map.seams[two[0]].a == prev || map.seams[two[0]].b == prev
                                  ? map.seams[two[1]]
                                  : map.seams[two[0]];
        prev = at;
        at = next.a == at ? next.b : next.a;
      }
      if (!kept(at)) continue;  // ends at a missing vertex, counted above
      expected.push_back({std::min(from, at), std::max(from, at), e.faces});
    }
  }
  std::sort(expected.begin(), expected.end(), ByEnds);
  expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
  return expected;
}

}  // namespace

absl::StatusOr<RejoinReport> RejoinSeams(RawMesh& output, const std::vector<uint32_t>& vertex_ids,
                                         const SeamMap& map) {
  const size_t nv = output.num_vertices();
  if (vertex_ids.size() != nv)
    return absl::InvalidArgumentError(
        absl::StrCat("rejoin: ", vertex_ids.size(), " vertex ids for ", nv, " output vertices"));
  if (absl::Status s = CheckArrays(output); !s.ok()) return s;
  RejoinReport report;
  if (map.original.empty()) {  // nothing was split
    report.input_vertex = vertex_ids;
    return report;
  }
  std::vector<uint8_t> is_seam(map.original.size(), 0);
  for (uint32_t w : map.seam_vertices) is_seam[w] = 1;
  for (uint32_t id : vertex_ids)
    if (id >= map.original.size())
      return absl::InvalidArgumentError(absl::StrCat("rejoin: vertex id ", id, " beyond the ",
                                                     map.original.size(), " of the split mesh"));

  // The first output copy of each input seam vertex stays; later ones merge into it.
  std::vector<uint32_t> first_copy(map.input_vertices, kNoIndex), new_index(nv);
  std::vector<float> positions;
  positions.reserve(output.positions.size());
  uint32_t next = 0;
  for (uint32_t o = 0; o < nv; ++o) {
    const uint32_t w = vertex_ids[o], v = map.original[w];
    if (is_seam[w]) {
      if (first_copy[v] != kNoIndex) {
        new_index[o] = first_copy[v];
        ++report.merged_vertices;
        continue;
      }
      first_copy[v] = next;
    }
    new_index[o] = next++;
    positions.insert(positions.end(), &output.positions[3 * o], &output.positions[3 * o] + 3);
    report.input_vertex.push_back(v);
  }
  output.positions = std::move(positions);
  for (uint32_t& c : output.triangles) c = new_index[c];
  for (uint32_t& l : output.locked_vertices) l = new_index[l];
  std::sort(output.locked_vertices.begin(), output.locked_vertices.end());
  output.locked_vertices.erase(
      std::unique(output.locked_vertices.begin(), output.locked_vertices.end()),
      output.locked_vertices.end());

  // Seam vertices may be gone only as inner points of a seam curve (engine/seam_collapse.h):
  // the expected seams are the input's with those left out, their chains merged into one edge.
  const std::vector<EdgeUse> expected =
      SeamsWithout(map, first_copy, &report.missing_seam_vertices);

  // The output's non-manifold edges in input numbering, against the expected seams.
  std::vector<EdgeUse> found;
  for (EdgeUse e : NonManifoldEdges(output)) {
    const uint32_t a = report.input_vertex[e.a], b = report.input_vertex[e.b];
    found.push_back({std::min(a, b), std::max(a, b), e.faces});
  }
  std::sort(found.begin(), found.end(), ByEnds);
  size_t i = 0, j = 0;
  while (i < expected.size() || j < found.size()) {
    const bool take_seam =
        j == found.size() || (i < expected.size() && !ByEnds(found[j], expected[i]));
    const bool take_found =
        i == expected.size() || (j < found.size() && !ByEnds(expected[i], found[j]));
    if (take_seam && take_found) {
      if (expected[i].faces != found[j].faces) report.changed_seams.push_back(found[j]);
      ++i, ++j;
    } else if (take_seam) {
      report.changed_seams.push_back({expected[i].a, expected[i].b, 0});
      ++i;
    } else {
      report.new_seams.push_back(found[j]);
      ++j;
    }
  }
  return report;
}

}  // namespace femsimp
