// Seams of assemblies (issue 12, item 2): parts that share a face or an edge meet at edges of
// three or more faces, which the half-edge mesh cannot hold. SplitSeams cuts the soup there into
// manifold sheets whose seam vertices are locked; after the simplification RejoinSeams merges the
// copies again, so that every part meeting at a seam uses the same seam vertices.
//
//   SeamMap map = *SplitSeams(raw);            // raw.locked_vertices now holds the seam vertices
//   Mesh mesh = *Mesh::Build(raw);
//   Simplify(mesh, options);
//   std::vector<uint32_t> ids;
//   RawMesh out = mesh.ToRaw(&ids);
//   RejoinReport report = *RejoinSeams(out, ids, map);  // report.conforming()
//
// A non-manifold edge (a seam) is one used by three or more faces, or by two faces in the same
// direction; RepairMesh's `seams` are exactly these once it has oriented the mesh.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/edge_groups.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// An undirected edge (a < b) and how many faces use it.
struct EdgeUse {
  uint32_t a = 0, b = 0;
  uint32_t faces = 0;
  bool operator==(const EdgeUse&) const = default;
};

// The non-manifold edges of a soup, ordered by (a, b). Indices must be in range.
std::vector<EdgeUse> NonManifoldEdges(const RawMesh& mesh);

struct SeamMap {
  size_t input_vertices = 0;
  // Per vertex of the split mesh: the input vertex it stands for. Input vertices keep their
  // index (for their first fan); copies are appended.
  std::vector<uint32_t> original;
  // Split-mesh vertices on a seam (every copy, and the endpoints of every seam edge), ascending:
  // these are locked and merged back by RejoinSeams.
  std::vector<uint32_t> seam_vertices;
  // The input's non-manifold edges, in input vertex numbering.
  std::vector<EdgeUse> seams;
  size_t split_vertices = 0;  // input vertices given more than one copy
  size_t copies = 0;          // vertices added

  bool empty() const { return seam_vertices.empty(); }
};

// Makes `mesh` manifold without moving a point or changing a face's order, group or fields:
// faces stay adjacent across an edge only where exactly two faces use it in opposite directions,
// and every vertex gets one copy per fan of faces connected that way around it. A seam edge so
// becomes a boundary edge of each sheet that uses it once (two faces of one sheet that close a
// fan around both its ends stay adjacent there). Sheets stay separate components. Seam vertices
// are added to mesh.locked_vertices (as are the copies of vertices locked before).
// A mesh without non-manifold edges or vertices comes back untouched, with an empty map.
// InvalidArgument if an index is out of range or the arrays do not agree. `edges`: the soup's
// edge groups when the caller has them (made from mesh.triangles as given), else made here.
absl::StatusOr<SeamMap> SplitSeams(RawMesh& mesh, const EdgeGroups* edges = nullptr);

struct RejoinReport {
  size_t merged_vertices = 0;  // output vertices merged into another copy of their input vertex
  // Per output vertex (after the merge): the input vertex of SplitSeams it stands for.
  std::vector<uint32_t> input_vertex;
  // Where the output's non-manifold edges differ from the input's seams (input numbering):
  // seams whose face count changed or that were lost, and non-manifold edges that are new.
  std::vector<EdgeUse> changed_seams, new_seams;
  size_t missing_seam_vertices = 0;  // input seam vertices absent from the output

  bool conforming() const {
    return changed_seams.empty() && new_seams.empty() && missing_seam_vertices == 0;
  }
};

// Merges the output vertices that are copies of one input seam vertex into the first of them
// (output order kept, the others dropped), renumbers the faces and locked vertices, and checks
// that the output's non-manifold edges are the input's seams with the same face counts.
// `vertex_ids`: per output vertex, its vertex in the mesh SplitSeams made (Mesh::ToRaw's
// vertex_ids). InvalidArgument if they do not fit the map or the output.
absl::StatusOr<RejoinReport> RejoinSeams(RawMesh& output, const std::vector<uint32_t>& vertex_ids,
                                         const SeamMap& map);

}  // namespace femsimp
