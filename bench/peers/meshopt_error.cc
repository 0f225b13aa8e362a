#include "bench/peers/meshopt_error.h"

#include <vector>

#include <meshoptimizer.h>

namespace femsimp::bench {

PeerRun RunMeshoptError(const RawMesh& input, double tolerance) {
  PeerRun run;
  const size_t nv = input.num_vertices();
  // target_error is relative to meshoptimizer's extent, which meshopt_simplifyScale returns (the
  // largest side of the bounding box in 0.18), not to the diagonal: divide by it, as its header
  // says to for an absolute error.
  const float scale = meshopt_simplifyScale(input.positions.data(), nv, 3 * sizeof(float));
  const float target_error = scale > 0 ? static_cast<float>(tolerance / scale) : 0.0f;
  std::vector<uint32_t> out(input.triangles.size());  // the worst case: nothing removed
  RunTimer timer(run);
  const size_t n = meshopt_simplify(out.data(), input.triangles.data(), input.triangles.size(),
                                    input.positions.data(), nv, 3 * sizeof(float),
                                    /*target_index_count=*/0, target_error, /*options=*/0,
                                    /*result_error=*/nullptr);
  timer.Stop();
  run.output = CompactSoup(input.positions, out.data(), n / 3);
  return run;
}

}  // namespace femsimp::bench
