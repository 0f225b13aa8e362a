// Preparing an input for the engine, the one way both femsimp (local mode) and femsimp-server
// take: Load → Repair → Build.
//
//   RawMesh (reader or upload) ──► RepairMesh (on: repair and report; off: strict check that
//   refuses naming every defect) ──► [seams: not supported yet] ──► Mesh::Build ──► PreparedMesh
#pragma once

#include <vector>

#include "absl/status/statusor.h"
#include "engine/mesh.h"
#include "engine/raw_mesh.h"
#include "engine/repair.h"

namespace femsimp {

struct PreparedMesh {
  Mesh mesh;
  // What the repair stage changed (empty in strict mode, where nothing may be changed).
  RepairReport report;
  // The non-manifold edges kept as seams; empty until seams are supported (see PrepareMesh).
  std::vector<SeamEdge> seams;
};

// Repairs `raw` (options.mode kOn) or checks it strictly (kOff), then builds the engine's mesh.
// Errors are InvalidArgument with a message for the user who has only the input file:
//  - what no repair can fix (indices out of range, non-finite coordinates, nothing left), each
//    occurrence by facet;
//  - strict mode: every defect, by kind, facet and coordinates (options.max_records_per_kind
//    per kind, then "and N more");
//  - non-manifold edges (3 or more facets on one edge): not supported yet, each seam named by
//    its end points and facets;
//  - a component no orientation makes consistent (a Möbius-like surface), by facet.
// A mesh with nothing to repair is built exactly as Mesh::Build builds it (byte-identical
// output).
absl::StatusOr<PreparedMesh> PrepareMesh(RawMesh raw, const RepairOptions& options);

}  // namespace femsimp
