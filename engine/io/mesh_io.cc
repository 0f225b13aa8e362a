#include "engine/io/mesh_io.h"

namespace femsimp {

const std::vector<std::string>& SupportedMeshExtensions() {
  static const std::vector<std::string> kExt = {".off", ".obj", ".stl", ".ply"};
  return kExt;
}

absl::StatusOr<RawMesh> ReadMeshFile(const std::string&) {
  return absl::UnimplementedError("mesh I/O in progress");
}

absl::Status WriteMeshFile(const std::string&, const RawMesh&) {
  return absl::UnimplementedError("mesh I/O in progress");
}

}  // namespace femsimp
