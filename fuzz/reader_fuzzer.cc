// libFuzzer target for one of femsimp's mesh file readers (engine/io/mesh_readers.h, msh.h): the
// input is the file, the reader is picked at build time (FEMSIMP_FUZZ_READER, fuzz/CMakeLists.txt),
// so each reader has its own target, corpus and execution count. A file the reader accepts goes
// on through the repair stage and Mesh::Build, as an upload would. Built with libFuzzer, ASan and
// UBSan (FEMSIMP_FUZZ=ON, clang); in every other build the same function replays the seeds and
// the kept crashes under ctest (replay_main.cc).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "absl/strings/string_view.h"
#include "engine/io/mesh_readers.h"
#include "fuzz/fuzz_check.h"

namespace {

enum class Reader { kOff, kObj, kStlAscii, kStlBinary, kPly, kMsh };
constexpr Reader kReader = Reader::FEMSIMP_FUZZ_READER;

constexpr absl::string_view Extension(Reader r) {
  switch (r) {
    case Reader::kOff:
      return ".off";
    case Reader::kObj:
      return ".obj";
    case Reader::kStlAscii:
    case Reader::kStlBinary:
      return ".stl";
    case Reader::kPly:
      return ".ply";
    case Reader::kMsh:
      return ".msh";
  }
  return "";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  absl::string_view file(reinterpret_cast<const char*>(data), size);
  // The STL reader takes a file as binary exactly when its size matches the triangle count in
  // its header, which random bytes almost never do: the ASCII target leaves those to the binary
  // one (and reaches the reading of a binary file whose count does not fit its size with the
  // rest), and the binary target writes the count that fits the (cut) size into the header.
  std::string binary;
  if constexpr (kReader == Reader::kStlAscii || kReader == Reader::kStlBinary) {
    const bool binary_sized = size >= 84 && [&] {
      uint32_t n;
      std::memcpy(&n, data + 80, 4);
      return size == 84 + 50 * uint64_t{n};
    }();
    if constexpr (kReader == Reader::kStlAscii) {
      if (binary_sized) return 0;
    } else {
      if (size < 84) return 0;
      const uint32_t n = static_cast<uint32_t>((size - 84) / 50);
      binary.assign(file.data(), 84 + 50 * size_t{n});
      std::memcpy(binary.data() + 80, &n, 4);
      file = binary;
    }
  }
  absl::StatusOr<femsimp::ParsedMeshFile> parsed = femsimp::ParseMeshFile(Extension(kReader), file);
  femsimp::fuzz::RequireMessage(parsed.status());
  // Each hole-fill mode in turn (by the input's size), so that the flat fill sees every corpus,
  // and every other size with overlapping bodies united (--unite-overlaps), which no plain
  // call reaches.
  femsimp::RepairOptions options;
  options.fill_holes = static_cast<femsimp::HoleFill>(size % 3);
  options.unite_overlaps = (size / 3) % 2 == 1;
  if (parsed.ok()) femsimp::fuzz::Prepare(std::move(parsed->mesh), options);
  return 0;
}
