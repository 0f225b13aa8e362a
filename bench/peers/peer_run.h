// One simplifier run of the fidelity table (bench/fidelity_table.cc): each tool's adapter takes
// the same input soup and a tolerance and hands back its output soup and its engine time.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp::bench {

struct PeerRun {
  std::string error;  // empty when the run worked
  RawMesh output;
  // The tool's own work only: turning the input soup into the tool's mesh and the output back
  // into a soup are not counted, for any tool. CPU seconds of the process (all its threads):
  // on a machine shared with other work they are what the run costs, where the wall time
  // depends on the load; single-threaded runs take about as long alone.
  double seconds = 0.0;
  double wall_seconds = 0.0;
  bool timed_out = false;  // stopped at the time limit: `output` is where it had got to
};

double ProcessCpuSeconds();

// Measures the CPU and wall time of one run's work into `run`.
class RunTimer {
 public:
  explicit RunTimer(PeerRun& run);
  void Stop();

 private:
  PeerRun& run_;
  double cpu0_;
  std::chrono::steady_clock::time_point wall0_;
};

// The faces `triangles` (nf of them, indices into `positions`) with only the vertices they use,
// numbered in order of first use: for tools that return an index buffer into the input's
// vertices.
RawMesh CompactSoup(const std::vector<float>& positions, const uint32_t* triangles, size_t nf);

}  // namespace femsimp::bench
