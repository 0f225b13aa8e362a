#include "bench/peers/peer_run.h"

#include <ctime>
#include <limits>

namespace femsimp::bench {

double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

RunTimer::RunTimer(PeerRun& run)
    : run_(run), cpu0_(ProcessCpuSeconds()), wall0_(std::chrono::steady_clock::now()) {}

void RunTimer::Stop() {
  run_.seconds = ProcessCpuSeconds() - cpu0_;
  run_.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
}

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
