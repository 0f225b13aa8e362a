#ifndef FEMSIMP_CELLSIM_DMA_ENGINE_H_
#define FEMSIMP_CELLSIM_DMA_ENGINE_H_

#include <array>
#include <cstddef>
#include <cstdint>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "cellsim/cost_model.h"
#include "cellsim/cycle_clock.h"
#include "cellsim/local_store.h"
#include "cellsim/main_memory.h"
#include "cellsim/spe_hooks.h"

namespace femsimp::cellsim {

// The memory flow controller (MFC) of one SPE: asynchronous copies between its local store and
// main memory.
//
// Requests: both addresses 16-byte aligned, size a positive multiple of 16 up to 16 KiB (the
// MFC's limit; its 1/2/4/8-byte transfers and DMA lists are not emulated), the LS range inside
// the SPE's LocalStore, the EA range inside one registered MainMemory region. Anything else is
// rejected with InvalidArgument / OutOfRange and nothing is transferred.
//
// Data and time are separate. The data moves when the request is issued (in issue order, one
// legal order for the hardware), so a put is visible in main memory at once: the non-coherence
// that matters is the readers' caches. Time follows the CostModel: a request issued at t on a
// free channel completes at t + latency + ceil(bytes / bytes_per_cycle); gets and puts each
// have one channel whose byte time is serialised. Each request belongs to a tag group
// (0..31); WaitTagMask blocks (in model time) until every request issued so far in the groups
// of the mask has completed. The fenced variants (GetF/PutF, as mfc_getf/mfc_putf) start only
// after every earlier request of the same tag group has completed.
//
// Other SPEs read and write the same main memory concurrently. The hardware moves aligned
// quadwords atomically; the emulation moves each quadword as two relaxed atomic 8-byte halves
// (std::atomic_ref<uint64_t>), so ThreadSanitizer sees no race, and a concurrent reader may see
// one half old and one new. Consumers that need a consistent quadword across SPEs publish it
// with the AtomicUnit (release) and read it after an acquire, as the engine does with the
// vertex status words. The local-store side is private to the SPE and copied plainly.
class DmaEngine {
 public:
  static constexpr size_t kMaxTransferBytes = 16 * 1024;
  static constexpr unsigned kNumTags = 32;

  DmaEngine(LocalStore* ls, const MainMemory* memory, CycleClock* clock, SpeCounters* counters,
            const CostModel* cost, Waiter* waiter)
      : ls_(ls),
        memory_(memory),
        clock_(clock),
        counters_(counters),
        cost_(cost),
        waiter_(waiter) {}

  // Main memory -> local store. Returns the modeled completion cycle.
  absl::StatusOr<uint64_t> Get(void* ls, uint64_t ea, size_t size, unsigned tag) {
    return Issue(Dir::kGet, ls, ea, size, tag, /*fenced=*/false);
  }
  // Local store -> main memory. Returns the modeled completion cycle.
  absl::StatusOr<uint64_t> Put(const void* ls, uint64_t ea, size_t size, unsigned tag) {
    return Issue(Dir::kPut, const_cast<void*>(ls), ea, size, tag, /*fenced=*/false);
  }
  // Fenced: ordered after all earlier requests of the same tag group.
  absl::StatusOr<uint64_t> GetF(void* ls, uint64_t ea, size_t size, unsigned tag) {
    return Issue(Dir::kGet, ls, ea, size, tag, /*fenced=*/true);
  }
  absl::StatusOr<uint64_t> PutF(const void* ls, uint64_t ea, size_t size, unsigned tag) {
    return Issue(Dir::kPut, const_cast<void*>(ls), ea, size, tag, /*fenced=*/true);
  }

  // Waits until every request issued so far in the tag groups of `mask` (bit i = tag i) has
  // completed; stalls the clock or, with software threads, lets another thread run.
  absl::Status WaitTagMask(uint32_t mask);
  // Tag groups of `mask` whose requests have all completed by now (no waiting; mfc_stat-like).
  uint32_t CompletedTagMask(uint32_t mask) const;
  // Modeled cycle at which the last request issued in `tag` completes (0 if none).
  uint64_t TagCompletionCycle(unsigned tag) const { return tag < kNumTags ? tag_done_[tag] : 0; }

  void set_put_observer(PutObserver* observer) { put_observer_ = observer; }

 private:
  enum class Dir { kGet, kPut };
  absl::StatusOr<uint64_t> Issue(Dir dir, void* ls, uint64_t ea, size_t size, unsigned tag,
                                 bool fenced);
  absl::Status Validate(Dir dir, const void* ls, uint64_t ea, size_t size, unsigned tag) const;

  LocalStore* ls_;
  const MainMemory* memory_;
  CycleClock* clock_;
  SpeCounters* counters_;
  const CostModel* cost_;
  Waiter* waiter_;
  PutObserver* put_observer_ = nullptr;
  std::array<uint64_t, kNumTags> tag_done_{};
  uint64_t get_channel_free_ = 0;
  uint64_t put_channel_free_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_DMA_ENGINE_H_
