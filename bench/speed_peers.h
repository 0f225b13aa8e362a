// The peers' speed runs shared by femsimp_bench and speed_table: OpenMesh's Decimater and
// meshoptimizer's meshopt_simplify to a count, each timed and its heap peak measured the same
// way (bench/heap_counter.h).
#pragma once

#include <cstdint>

#include "engine/raw_mesh.h"

namespace femsimp::bench {

struct SpeedSample {
  double seconds = 0;        // engine time: only the simplification
  double build_seconds = 0;  // the tool's mesh built from the soup (femsimp: PrepareMesh or
                             // Mesh::Build; OpenMesh: TriMesh construction; meshoptimizer: none)
  double cpu_seconds = 0;    // CPU time of the simplification, all threads
  int64_t total_bytes = 0;   // peak heap beyond the input soup over build + simplification
  int64_t work_bytes = 0;    // peak heap during the simplification beyond its input structure
};

// OpenMesh Decimater with quadric, normal-flipping and aspect-ratio modules, decimate_to
// `target_vertices`. `output` (optional) receives the result as a soup.
SpeedSample RunOpenMeshDecimater(const RawMesh& in, uint64_t target_vertices, RawMesh* output);

// meshopt_simplify to `target_faces` with no error bound and the border locked (the open
// boundary kept, as femsimp and OpenMesh keep it). `output` (optional) receives the result.
SpeedSample RunMeshoptSimplify(const RawMesh& in, uint64_t target_faces, RawMesh* output);

}  // namespace femsimp::bench
