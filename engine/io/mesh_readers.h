// femsimp's own mesh file readers: one pass over the bytes of an OFF (text or binary), OBJ, STL
// (ASCII or binary), PLY (ASCII, binary little- or big-endian) or gmsh MSH (2.2 or 4.1, ASCII or
// binary; msh.h) file yields the triangle soup with its face groups and fields (face_data.h says
// which format holds what).
//
// A reader refuses what makes the file unreadable, and says where: a number it cannot parse, a
// coordinate that is not a finite float, a face of fewer than 3 or more than kMaxPolygonCorners
// corners, a negative vertex index or one beyond the file's vertices, a file that ends before its
// header says. Faces of 4 to kMaxPolygonCorners corners are cut into triangles (polygons.h) and
// the warnings say how many. Geometric and
// topological defects (degenerate, duplicate, flipped or non-manifold faces) are not the
// reader's business: they reach the soup as they are, for the repair stage (engine/repair.h) or,
// with repair off, for validation (Mesh::Build, engine/mesh_checks.h) to report.
//
// Results are those of OpenMesh 9's readers, which femsimp used before, for a part near the
// origin: coordinates parsed as a C++ stream parses a double and rounded to float (binary
// values of another type converted to float); STL facets share a vertex where their corners are
// equal as floats (the first appearance gives the vertex its index). A part far from the origin
// for its size is held relative to a local origin near it instead (engine/local_origin.h), the
// floats taken of the coordinates minus the origin.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "engine/io/face_data.h"
#include "engine/raw_mesh.h"

namespace femsimp {

struct ParsedMeshFile {
  RawMesh mesh;  // with face groups (OBJ, PLY, MSH) and fields (PLY) where the file has them
  GroupNames
      group_names;  // OBJ: the names that are not "default" or "group_<id>"; MSH: $PhysicalNames
  // What the reader read past without refusing the file, one line each for the CLI's summary
  // (MSH: "msh: left out 1234 tetrahedra, 56 lines").
  std::vector<std::string> warnings;
};

// `ext` is the lower-case extension with the dot. Errors are InvalidArgument with a message
// (without the path) naming the problem and where: line, byte, vertex, face or facet index.
absl::StatusOr<ParsedMeshFile> ParseMeshFile(absl::string_view ext, absl::string_view data);

}  // namespace femsimp
