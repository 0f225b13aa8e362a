// Builds the benchmark's blade-scale meshes: Loop subdivision of a mesh, written as binary PLY
// after each requested level (levels ascending, so level 4 reuses the level-3 result).
#include <cstddef>  // before LoopT.hh: OpenMesh 9.0's SubdividerT.hh uses size_t unqualified
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "engine/io/openmesh.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#pragma GCC diagnostic pop

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s IN_MESH OUT_PREFIX LEVEL...\n  writes OUT_PREFIX<LEVEL>.ply\n",
                 argv[0]);
    return 2;
  }
  TriMesh mesh;
  if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  std::vector<int> levels;
  for (int i = 3; i < argc; ++i) levels.push_back(std::atoi(argv[i]));
  int done = 0;
  for (int level : levels) {
    if (level < done) {
      std::fprintf(stderr, "levels must ascend\n");
      return 2;
    }
    if (level > done) {
      OpenMesh::Subdivider::Uniform::LoopT<TriMesh> loop;
      loop.attach(mesh);
      loop(static_cast<size_t>(level - done));
      loop.detach();
      done = level;
    }
    const std::string out = std::string(argv[2]) + std::to_string(level) + ".ply";
    if (!OpenMesh::IO::write_mesh(mesh, out, OpenMesh::IO::Options::Binary)) {
      std::fprintf(stderr, "cannot write %s\n", out.c_str());
      return 1;
    }
    std::printf("%s level=%d vertices=%zu faces=%zu\n", out.c_str(), level, mesh.n_vertices(),
                mesh.n_faces());
  }
  return 0;
}
