// A cheap pass over a mesh file before OpenMesh reads it. OpenMesh 9.0's readers accept
// truncated files (OFF and ASCII PLY repeat the last face, OFF reads face lines as vertices),
// turn unparsable or "nan" numbers into zeros or shift the following vertices, and silently
// drop faces (degenerate STL facets and OBJ faces, OBJ faces with fewer than three corners).
// The survey checks what those readers do not and counts the elements, so that the caller
// can verify OpenMesh returned exactly what the file holds.
#pragma once

#include <cstddef>
#include <string>

#include "absl/strings/string_view.h"

#include "absl/status/statusor.h"

namespace femsimp {

struct MeshFileSurvey {
  size_t vertices = 0;  // as stored in the file (STL: corners, 3 per facet)
  size_t faces = 0;
  bool binary = false;  // for OpenMesh's read options (STL is detected by OpenMesh itself)
};

// `ext` is the lower-case extension with the dot. Errors are InvalidArgument with a message
// (without the path) naming the problem and where: line, vertex or face index, counts.
absl::StatusOr<MeshFileSurvey> SurveyMeshFile(absl::string_view ext, absl::string_view data);

}  // namespace femsimp
