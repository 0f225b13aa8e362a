// Preparing an input for the engine, the one way both femsimp (local mode) and femsimp-server
// take: Load → Repair → Build.
//
//   RawMesh (reader or upload) ──► RepairMesh (on: repair and report; off: strict check that
//   refuses naming every defect) ──► SplitSeams (assemblies: sheets with locked seam vertices)
//   ──► Mesh::Build ──► PreparedMesh ──► Simplify ──► OutputMesh (seams rejoined, shared
//   surfaces written once per body)
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/mesh.h"
#include "engine/raw_mesh.h"
#include "engine/repair.h"
#include "engine/seams.h"

namespace femsimp {

// Wall seconds of PrepareMesh's steps, for callers that report them (the server's per-stage
// metrics).
struct PrepareTimes {
  double repair_seconds = 0;  // RepairMesh (or the strict check) and SplitSeams
  double order_seconds = 0;   // SortSpatially
  double build_seconds = 0;   // Mesh::Build
};

// A closed surface two bodies share whole, kept and simplified once (RepairKind::kSharedShell):
// its faces' sides index, and per face group of the kept copy the group of the copy facing the
// other way (RepairResult::SharedShell).
struct SharedWall {
  uint32_t sides;
  std::vector<std::pair<uint32_t, uint32_t>> twin_groups;
};

struct PreparedMesh {
  Mesh mesh;
  // What the repair stage changed (empty in strict mode, where nothing may be changed).
  RepairReport report;
  // The non-manifold edges kept as seams, and how the mesh was split along them.
  std::vector<SeamEdge> seams;
  SeamMap seam_map;
  // The surfaces two bodies share whole that the parts now bound (engine/enclosed_parts.h).
  std::vector<SharedWall> shared_walls;
  PrepareTimes times;
};

// Repairs `raw` (options.mode kOn) or checks it strictly (kOff), then builds the engine's mesh.
// Errors are InvalidArgument with a message for the user who has only the input file:
//  - what no repair can fix (indices out of range, non-finite coordinates, nothing left), each
//    occurrence by facet;
//  - strict mode: every defect, by kind, facet and coordinates (options.max_records_per_kind
//    per kind, then "and N more");
//  - a component no orientation makes consistent (a Möbius-like surface), by facet.
// The soup is renumbered in curve order (engine/spatial_order.h) before it is built: a mesh
// with nothing to repair is built as Mesh::Build builds it after SortSpatially (byte-identical
// output).
absl::StatusOr<PreparedMesh> PrepareMesh(RawMesh raw, const RepairOptions& options);

// The simplified mesh as the user's input stands for it: compacted, and the sheets of an
// assembly joined again at their seams. FailedPrecondition if a seam did not stay conforming
// (the seam vertices are locked, so this means a bug, never a silently wrong output), naming
// the first edge that differs by its ends' positions. A shared wall is written twice, as each
// body had it: the kept faces (into the inner body), then each turned over with its twin group
// and the same fields.
absl::StatusOr<RawMesh> OutputMesh(const Mesh& mesh, const SeamMap& seams,
                                   const std::vector<SharedWall>& walls);

}  // namespace femsimp
