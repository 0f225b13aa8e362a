// A cheap pass over a mesh file before OpenMesh reads it. OpenMesh 9.0's readers accept
// truncated files (OFF and ASCII PLY repeat the last face, OFF reads face lines as vertices),
// turn unparsable or "nan" numbers into zeros or shift the following vertices, and silently
// drop faces (degenerate STL facets and OBJ faces, OBJ faces with fewer than three corners).
// The survey checks what those readers do not and counts the elements, so that the caller
// can verify OpenMesh returned exactly what the file holds. It also collects the face groups
// and fields, which OpenMesh's readers cannot hand to a raw importer (face_data.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/strings/string_view.h"

#include "absl/status/statusor.h"
#include "engine/io/face_data.h"
#include "engine/raw_mesh.h"

namespace femsimp {

struct MeshFileSurvey {
  size_t vertices = 0;  // as stored in the file (STL: corners, 3 per facet)
  size_t faces = 0;
  bool binary = false;  // for OpenMesh's read options (STL is detected by OpenMesh itself)
  // One id per face (OBJ `g`, PLY "group"), or empty: no groups, or all in group 0.
  std::vector<uint32_t> face_groups;
  GroupNames group_names;              // OBJ: the names that are not "default" or "group_<id>"
  std::vector<FaceField> face_fields;  // PLY float face properties
};

// `ext` is the lower-case extension with the dot. Errors are InvalidArgument with a message
// (without the path) naming the problem and where: line, vertex or face index, counts.
absl::StatusOr<MeshFileSurvey> SurveyMeshFile(absl::string_view ext, absl::string_view data);

}  // namespace femsimp
