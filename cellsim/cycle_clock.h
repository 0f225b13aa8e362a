#ifndef FEMSIMP_CELLSIM_CYCLE_CLOCK_H_
#define FEMSIMP_CELLSIM_CYCLE_CLOCK_H_

#include <cstdint>

#include "cellsim/counters.h"

namespace femsimp::cellsim {

// The modeled time of one SPE. Now() only moves forward; each advance is also added to the
// counter of its cause, so that SpeCounters::ModeledCycles() equals the time that passed since
// the counters were last reset. One SPU runs one software thread at a time, so the software
// threads of an SPE share this clock.
class CycleClock {
 public:
  explicit CycleClock(SpeCounters* counters) : counters_(counters) {}

  uint64_t Now() const { return now_; }

  void AddCompute(uint64_t n) { Charge(&SpeCounters::compute_cycles, n); }
  void AddCache(uint64_t n) { Charge(&SpeCounters::cache_cycles, n); }
  void AddDmaIssue(uint64_t n) { Charge(&SpeCounters::dma_issue_cycles, n); }
  void AddAtomic(uint64_t n) { Charge(&SpeCounters::atomic_cycles, n); }
  void AddSwitch(uint64_t n) { Charge(&SpeCounters::switch_cycles, n); }
  // Stalls until `cycle` (a transfer's completion); no-op when it is already past.
  void StallUntil(uint64_t cycle) {
    if (cycle > now_) Charge(&SpeCounters::dma_stall_cycles, cycle - now_);
  }
  // Waits until `cycle`, when the work it asked for is published; no-op when it is past.
  void WaitForWorkUntil(uint64_t cycle) {
    if (cycle > now_) Charge(&SpeCounters::work_wait_cycles, cycle - now_);
  }

 private:
  void Charge(uint64_t SpeCounters::*field, uint64_t n) {
    now_ += n;
    counters_->*field += n;
  }

  SpeCounters* counters_;
  uint64_t now_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_CYCLE_CLOCK_H_
