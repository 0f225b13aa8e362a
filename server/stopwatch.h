// Wall time since construction or the last Restart, for the per-stage metrics.
#pragma once

#include <chrono>

namespace femsimp::server {

class Stopwatch {
 public:
  void Restart() { start_ = Clock::now(); }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_ = Clock::now();
};

}  // namespace femsimp::server
