#ifndef FEMSIMP_CELLSIM_SOFT_THREADS_H_
#define FEMSIMP_CELLSIM_SOFT_THREADS_H_

#include <ucontext.h>

#include <cstddef>
#include <cstdint>
#include <functional>

#include "absl/status/status.h"
#include "cellsim/cost_model.h"
#include "cellsim/cycle_clock.h"
#include "cellsim/local_store.h"

namespace femsimp::cellsim {

// Software-managed threads inside one SPE (Bader et al., used by the paper to hide cache-miss
// latency): K cooperative threads on the SPE's host thread, switched with ucontext, each with a
// stack (and control block) allocated from the SPE's local store, so stacks count against the
// 256 KiB budget. Under ThreadSanitizer the switches go through its fiber API.
//
// A thread runs until it waits for a modeled cycle (a cache miss, a DMA wait) or yields; the
// scheduler then resumes, round robin, the next thread whose wait is over, charging
// thread_switch_cycles; if none is ready the SPE stalls until the earliest one is. So while one
// thread waits for its line the others' compute advances the one SPE clock, which is the
// latency hiding the model shows. A switch is counted only when the SPU leaves a live thread
// for another one (not when a thread ends, nor when the waiting thread is the only ready one).
//
// Stacks end in a canary; an overflow detected at a switch aborts with a message naming the
// stack size (an overflow may already have corrupted other local-store buffers).
class SoftThreadScheduler {
 public:
  using Body = std::function<void(int thread_index)>;

  SoftThreadScheduler(LocalStore* ls, CycleClock* clock, SpeCounters* counters,
                      const CostModel* cost)
      : ls_(ls), clock_(clock), counters_(counters), cost_(cost) {}
  SoftThreadScheduler(const SoftThreadScheduler&) = delete;
  SoftThreadScheduler& operator=(const SoftThreadScheduler&) = delete;

  // Runs body(0..k-1) on k threads and returns when all have returned. Fails without running
  // anything when k < 1, when already running, or when k stacks of `stack_bytes` (multiple of
  // 16, at least 4 KiB) plus control blocks do not fit in the local store; they are released
  // afterwards.
  absl::Status Run(int k, size_t stack_bytes, const Body& body);

  // True inside Run (on one of its threads).
  bool active() const { return current_ >= 0; }
  int current() const { return current_; }
  int num_threads() const { return num_threads_; }

  // Suspends the calling thread until the clock reaches `cycle`, running others meanwhile.
  // With one thread, or outside Run, it just stalls the clock.
  void WaitUntil(uint64_t cycle);
  // Lets another ready thread run (no-op when there is none).
  void Yield();

 private:
  struct Fiber;
  static void Trampoline(unsigned lo, unsigned hi);
  void InitFiber(Fiber& f);
  void SwitchToScheduler();
  void Resume(int index);
  int PickNext();
  void CheckCanary(int index) const;

  LocalStore* ls_;
  CycleClock* clock_;
  SpeCounters* counters_;
  const CostModel* cost_;
  const Body* body_ = nullptr;
  Fiber* fibers_ = nullptr;
  int num_threads_ = 0;
  int current_ = -1;
  int last_ = -1;
  size_t stack_bytes_ = 0;
  ucontext_t scheduler_context_;
  void* scheduler_tsan_fiber_ = nullptr;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_SOFT_THREADS_H_
