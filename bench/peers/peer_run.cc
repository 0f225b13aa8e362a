#include "bench/peers/peer_run.h"

#include <limits>

namespace femsimp::bench {

RawMesh CompactSoup(const std::vector<float>& positions, const uint32_t* triangles, size_t nf) {
  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  RawMesh out;
  std::vector<uint32_t> remap(positions.size() / 3, kUnused);
  for (size_t i = 0; i < 3 * nf; ++i) {
    uint32_t& r = remap[triangles[i]];
    if (r == kUnused) {
      r = static_cast<uint32_t>(out.positions.size() / 3);
      out.positions.insert(out.positions.end(), &positions[3 * triangles[i]],
                           &positions[3 * triangles[i]] + 3);
    }
    out.triangles.push_back(r);
  }
  return out;
}

}  // namespace femsimp::bench
