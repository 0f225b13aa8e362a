#ifndef FEMSIMP_CELLSIM_GUIDED_DISPENSER_H_
#define FEMSIMP_CELLSIM_GUIDED_DISPENSER_H_

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace femsimp::cellsim {

// The shared index of a guided run (WorkPlan::Guided): items 0..count-1 in order, an SPE that
// asks taking the next ceil(remaining / 2N) of them, at most the run's max_chunk (guided
// self-scheduling: long runs of neighbouring items first, single items at the end to even the
// SPEs out).
//
// On the machine the SPEs would take chunks with getllar/putllc on one line, in the order their
// requests reach it. Here every SPE is a host thread running at its own pace, so the requests
// are served in modeled time instead: an SPE that asked at modeled cycle t is served once it
// is the earliest of those waiting and every SPE still working has reported progress past t
// (Progress; ties go to the lower index). No request can then come earlier than the one
// served, so the split depends on the modeled clocks alone, never on the host's scheduling;
// the SPEs still run side by side on the host between requests.
//
// A run may publish its items over time (`published_at`, non-decreasing: item i may be taken
// from that cycle of the run on, as when the PPE hands items over while it is still choosing
// them). A request is then served at the later of its own cycle and the next item's, with the
// items published by then, and the SPE waits until it is served.
class GuidedDispenser {
 public:
  // A run of `spes` SPEs over `count` items, at most `max_chunk` a request, item i published at
  // cycle published_at[i] of the run (all at 0 when null); every SPE counts as working, at
  // cycle 0. An SPE served at cycle t asks again at t + visit_cycles or later (what it pays for
  // the visit).
  void Begin(int spes, uint64_t count, uint64_t visit_cycles, uint64_t max_chunk,
             const uint64_t* published_at = nullptr);
  // What a request got: items [first, last), empty once every item has been taken, and the
  // cycle of the run it was served at (the request's own, or later when it waited for items).
  struct Grant {
    uint64_t first = 0, last = 0;
    uint64_t served_at = 0;
  };
  // SPE `spe`, `elapsed` modeled cycles into the run, asks for items; blocks until it is
  // served.
  Grant Take(int spe, uint64_t elapsed);
  // SPE `spe` has reached `elapsed` modeled cycles: it will not ask earlier.
  void Progress(int spe, uint64_t elapsed);
  // SPE `spe` will ask no more in this run (its kernel returned).
  void Finish(int spe);

  // How many items a request takes when `remaining` are left in a run of `spes` SPEs. The
  // sequence of chunk sizes is the same whichever SPEs ask, so a caller can lay its items out
  // chunk by chunk before the run.
  static uint64_t ChunkSize(uint64_t remaining, int spes, uint64_t max_chunk) {
    const uint64_t twice = 2 * static_cast<uint64_t>(std::max(spes, 1));
    return std::clamp<uint64_t>((remaining + twice - 1) / twice, 1,
                                std::max<uint64_t>(max_chunk, 1));
  }

 private:
  enum class State { kWorking, kWaiting, kServed, kDone };
  struct Slot {
    State state = State::kWorking;
    uint64_t asked_at = 0;
    Grant grant;                        // what it was served (at the serving, in serving order)
    std::atomic<uint64_t> progress{0};  // modeled cycles it is known to have reached
    std::condition_variable wake;
  };
  uint64_t PublishedAt(uint64_t item) const {
    return published_at_ == nullptr ? 0 : published_at_[item];
  }
  // Serves waiting SPEs while the earliest of them cannot be overtaken. Caller holds mu_.
  void ServeLocked();
  // Gives `slot` its chunk and wakes it; once the index is empty, wakes every waiting SPE
  // with nothing. Caller holds mu_.
  void GiveLocked(Slot& slot);

  std::mutex mu_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::atomic<int> waiting_{0};
  uint64_t next_ = 0, count_ = 0;
  uint64_t visit_cycles_ = 0;
  uint64_t max_chunk_ = 0;
  const uint64_t* published_at_ = nullptr;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_GUIDED_DISPENSER_H_
