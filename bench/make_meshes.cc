// Builds the benchmark's blade-scale meshes: Loop subdivision of a mesh, written as binary PLY
// after each requested level (levels ascending, so level 4 reuses the level-3 result).
#include <cstddef>  // before LoopT.hh: OpenMesh 9.0's SubdividerT.hh uses size_t unqualified
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "common/flags.h"
#include "engine/io/openmesh.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#pragma GCC diagnostic pop

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

int main(int argc, char** argv) {
  femsimp::flags::FlagSet flags("make_meshes");
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit = flags.ParseMain(
          argc, argv,
          "Usage: make_meshes IN_MESH OUT_PREFIX LEVEL...\n  writes OUT_PREFIX<LEVEL>.ply\n\n", "",
          &parsed))
    return *exit;
  const std::vector<std::string>& args = parsed.positional;
  if (args.size() < 3) {
    std::fprintf(stderr, "make_meshes: needs IN_MESH OUT_PREFIX LEVEL... (see --help)\n");
    return femsimp::flags::kUsageExit;
  }
  std::vector<int> levels;
  for (size_t i = 2; i < args.size(); ++i) {
    absl::StatusOr<double> level = femsimp::flags::ParseNumberIn(
        "LEVEL", args[i], femsimp::flags::NumberKind::kInteger, femsimp::Range::Closed(0, 8));
    if (!level.ok()) {
      std::fprintf(stderr, "make_meshes: %s\n", std::string(level.status().message()).c_str());
      return femsimp::flags::kUsageExit;
    }
    levels.push_back(static_cast<int>(*level));
  }
  TriMesh mesh;
  if (!OpenMesh::IO::read_mesh(mesh, args[0])) {
    std::fprintf(stderr, "cannot read %s\n", args[0].c_str());
    return 1;
  }
  int done = 0;
  for (int level : levels) {
    if (level < done) {
      std::fprintf(stderr, "levels must ascend\n");
      return femsimp::flags::kUsageExit;
    }
    if (level > done) {
      OpenMesh::Subdivider::Uniform::LoopT<TriMesh> loop;
      loop.attach(mesh);
      loop(static_cast<size_t>(level - done));
      loop.detach();
      done = level;
    }
    const std::string out = args[1] + std::to_string(level) + ".ply";
    if (!OpenMesh::IO::write_mesh(mesh, out, OpenMesh::IO::Options::Binary)) {
      std::fprintf(stderr, "cannot write %s\n", out.c_str());
      return 1;
    }
    std::printf("%s level=%d vertices=%zu faces=%zu\n", out.c_str(), level, mesh.n_vertices(),
                mesh.n_faces());
  }
  return 0;
}
