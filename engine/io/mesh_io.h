// Mesh files in and out, chosen by file extension. Every format is read by femsimp's own readers
// in one pass (mesh_readers.h) and written by femsimp's own writers (face_data.h: which format
// holds face groups and fields), which hold any soup, the seams of an assembly included.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/io/face_data.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// Lower-case extensions with the dot: ".off", ".obj", ".stl", ".ply", ".msh".
const std::vector<std::string>& SupportedMeshExtensions();

// Reads OFF, OBJ, STL (ascii or binary), PLY or gmsh MSH into an indexed triangle soup. File-level
// problems (missing, unreadable, truncated, unknown extension, non-triangle faces, indices beyond
// the file's vertices, non-finite coordinates, ...) come back as errors naming the file, the
// problem and where (mesh_readers.h). Geometric and topological defects are left to the repair
// stage (engine/prepare.h) and validation (Mesh::Build, engine/mesh_checks.h).
// Face groups come from OBJ, PLY and MSH files, face fields from PLY files; group_names, when
// given, receives the OBJ group names that are not derived from the id and MSH's physical names;
// warnings, when given, what the reader left out of the file (MSH: elements other than triangles).
absl::StatusOr<RawMesh> ReadMeshFile(const std::string& path, GroupNames* group_names = nullptr,
                                     std::vector<std::string>* warnings = nullptr);

// Writes the soup in the format of the path's extension (binary where the format has one,
// except OFF, OBJ and MSH which are written as text: MSH as 4.1 ASCII). OBJ groups and MSH
// physical groups are named from group_names. A mesh
// with groups or fields the format cannot hold is refused (CheckFormatHolds): drop them first
// (DropUnheldFaceData) to write it anyway.
absl::Status WriteMeshFile(const std::string& path, const RawMesh& mesh,
                           const GroupNames& group_names = {});

// Writes the soup as text in every format (ASCII STL and PLY), for inspection and tests.
absl::Status WriteMeshFileAscii(const std::string& path, const RawMesh& mesh,
                                const GroupNames& group_names = {});

// Lower-case extension of the path, with the dot (what picks the format).
std::string MeshFileExtension(const std::string& path);

}  // namespace femsimp
