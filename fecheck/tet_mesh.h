// A closed surface made into linear tetrahedra by tetgen, keeping the surface as given (-Y:
// every surface triangle is a face of the tetrahedral mesh, no point added on it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"
#include "fecheck/tools.h"

namespace femsimp::fecheck {

struct TetMesh {
  std::vector<double> nodes;    // x, y, z per node, in metres (the unit scale applied)
  std::vector<uint32_t> tets;   // four nodes per tetrahedron, positive volume
  int components = 0;           // node-connected parts (each has six rigid-body modes)
  int bodies_meshed_apart = 0;  // bodies that touch without shared faces, meshed each alone
  size_t num_nodes() const { return nodes.size() / 3; }
  size_t num_tets() const { return tets.size() / 4; }
};

// Facets written twice facing both ways (a surface two bodies share, written once per body)
// are left out of both functions: the two bodies are one solid, bonded, of one material.
//
// What tetgen needs of a surface: valid triangles (CheckSoup), closed (no boundary edge),
// enclosing a positive volume (oriented outwards), not crossing itself, and with faces
// overlapping in their plane (FindCrossings) only between bodies that touch (each meshed on its
// own by Tetrahedralise). InvalidArgument saying what is wrong.
absl::Status CheckClosedSolid(const RawMesh& surface);

// Runs tetgen on `surface` (written to run.dir; each body on its own where bodies touch without
// shared faces, so that they are not bonded) with the quality bound -q1.414 and, when
// max_tet_volume > 0, that volume bound in model units cubed; coordinates are multiplied by
// unit_scale afterwards. InvalidArgument quoting tetgen when it refuses the surface (e.g. a
// self-intersection), Cancelled, NotFound (no tetgen).
// keep_surface false lets tetgen split surface triangles (points on them, the geometry stays).
absl::StatusOr<TetMesh> Tetrahedralise(const RawMesh& surface, double unit_scale,
                                       double max_tet_volume, bool keep_surface,
                                       const ToolRun& run);

// A tetgen output table (.node, .ele): the numbers of each non-comment line; the first row is
// the header. InvalidArgument naming the file when it cannot be read or a number is malformed.
absl::StatusOr<std::vector<std::vector<double>>> ReadTetgenTable(const std::string& path);

}  // namespace femsimp::fecheck
