#ifndef FEMSIMP_CELLSIM_WORK_PLAN_H_
#define FEMSIMP_CELLSIM_WORK_PLAN_H_

#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cellsim/guided_dispenser.h"

namespace femsimp::cellsim {

// How one Runtime::Run hands out work items; SPE kernels (and their software threads) pull
// items with SpeContext::NextWorkItem until it returns nullopt.
//  - PerSpe: SPE i gets the values of lists[i], in order (the paper: candidates split
//    uniformly, each SPE visits its own in cost order). The lists must outlive the run.
//  - Shared: items 0..count-1 from one shared index, taken `chunk` at a time (dynamic load
//    balancing; each chunk is charged one getllar + putllc in atomic cycles). Served in the
//    order the host threads ask, so the split depends on the host's scheduling.
//  - Guided: items 0..count-1 from one shared index in chunks that shrink as it empties (at
//    most max_chunk each), served in modeled-time order (GuidedDispenser): the split depends on
//    the modeled clocks alone. Each visit to the index is charged one getllar + putllc. With
//    `published_at` (count cycles, non-decreasing, outliving the run) item i may be taken
//    from that cycle of the run on; an SPE that asks earlier waits for it.
//  - None: NextWorkItem returns nullopt at once.
class WorkPlan {
 public:
  enum class Kind { kNone, kPerSpe, kShared, kGuided };

  static WorkPlan None() { return WorkPlan(); }
  static WorkPlan PerSpe(std::vector<std::span<const uint32_t>> lists);
  static WorkPlan Shared(uint64_t count, uint64_t chunk = 1);
  static constexpr uint64_t kAnyChunk = ~uint64_t{0};
  static WorkPlan Guided(uint64_t count, uint64_t max_chunk = kAnyChunk,
                         const uint64_t* published_at = nullptr);

  Kind kind() const { return kind_; }
  const std::vector<std::span<const uint32_t>>& lists() const { return lists_; }
  uint64_t count() const { return count_; }
  uint64_t chunk() const { return chunk_; }  // Shared: each chunk; Guided: the largest
  const uint64_t* published_at() const { return published_at_; }

 private:
  Kind kind_ = Kind::kNone;
  std::vector<std::span<const uint32_t>> lists_;
  uint64_t count_ = 0;
  uint64_t chunk_ = 1;
  const uint64_t* published_at_ = nullptr;
};

// One SPE's position in a WorkPlan during a run.
class WorkCursor {
 public:
  void Begin(const WorkPlan* plan, std::atomic<uint64_t>* shared_next, GuidedDispenser* guided,
             int spe_index);
  void End() { *this = WorkCursor(); }
  // What Next did besides: whether it visited the shared index, and the cycle of the run it
  // was served at (it waits until then).
  struct Visit {
    bool took_chunk = false;
    uint64_t served_at = 0;
  };
  // The next item, or nullopt; `elapsed`: the SPE's modeled cycles since the run began.
  std::optional<uint64_t> Next(uint64_t elapsed, Visit* visit);

 private:
  const WorkPlan* plan_ = nullptr;
  std::atomic<uint64_t>* shared_next_ = nullptr;
  GuidedDispenser* guided_ = nullptr;
  int spe_index_ = 0;
  std::span<const uint32_t> list_;
  uint64_t pos_ = 0;
  uint64_t end_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_WORK_PLAN_H_
