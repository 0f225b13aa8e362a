// Mesh files in and out through OpenMesh's readers and writers, chosen by file extension.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// Lower-case extensions with the dot: ".off", ".obj", ".stl", ".ply".
const std::vector<std::string>& SupportedMeshExtensions();

// Reads OFF, OBJ, STL (ascii or binary) or PLY into an indexed triangle soup. File-level
// problems (missing, unreadable, truncated, unknown extension, non-triangle faces, ...) come
// back as errors naming the file and the problem. Topology is checked later by Mesh::Build.
absl::StatusOr<RawMesh> ReadMeshFile(const std::string& path);

// Writes the soup in the format of the path's extension (binary where the format has one,
// except OFF and OBJ which are written as text).
absl::Status WriteMeshFile(const std::string& path, const RawMesh& mesh);

// Writes the soup as text in every format (ASCII STL and PLY), for inspection and tests.
absl::Status WriteMeshFileAscii(const std::string& path, const RawMesh& mesh);

}  // namespace femsimp
