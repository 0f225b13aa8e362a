// libFuzzer target for femsimp's mesh file readers (issue 15: fuzzed readers), built with
// AddressSanitizer and UndefinedBehaviorSanitizer (FEMSIMP_FUZZ=ON, clang). The first byte picks
// the format, the rest is the file. A file the reader accepts goes on through the repair stage
// and Mesh::Build, as an upload would: whatever the bytes, the answer is a mesh or an error
// with a message, never a crash, a hang or undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "absl/strings/string_view.h"
#include "engine/io/mesh_readers.h"
#include "engine/prepare.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static constexpr absl::string_view kExtensions[] = {".off", ".obj", ".stl", ".ply", ".msh"};
  const absl::string_view ext = kExtensions[data[0] % 5];
  const absl::string_view file(reinterpret_cast<const char*>(data + 1), size - 1);
  absl::StatusOr<femsimp::ParsedMeshFile> parsed = femsimp::ParseMeshFile(ext, file);
  if (!parsed.ok()) {
    if (parsed.status().message().empty()) std::abort();  // every refusal says why
    return 0;
  }
  absl::StatusOr<femsimp::PreparedMesh> prepared =
      femsimp::PrepareMesh(std::move(parsed->mesh), femsimp::RepairOptions{});
  if (!prepared.ok() && prepared.status().message().empty()) std::abort();
  return 0;
}
