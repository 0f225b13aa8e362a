#ifndef FEMSIMP_CELLSIM_COUNTERS_H_
#define FEMSIMP_CELLSIM_COUNTERS_H_

#include <array>
#include <cstdint>
#include <string>

namespace femsimp::cellsim {

// Event and cycle counters of one SPE. Plain fields: only the SPE's own host thread writes
// them while a run is in progress; the PPE reads or resets them between runs. Sum several SPEs
// with operator+= (cycle sums are total work, not elapsed time: see Runtime::ElapsedCycles).
struct SpeCounters {
  // Software cache. A Read is a hit when its line was already present (also when a Touch
  // brought it in and the fill is still in flight), a miss when it had to start a fill (a
  // refetch after the line was evicted while its thread waited counts as one more miss).
  uint64_t cache_reads = 0;
  uint64_t cache_hits = 0;
  uint64_t cache_misses = 0;
  uint64_t cache_touches = 0;        // Touch / TouchReport calls.
  uint64_t cache_prefetches = 0;     // Fills started by a touch (not counted as misses).
  uint64_t cache_pending_waits = 0;  // Hits that still had to wait for an in-flight fill.
  uint64_t cache_evictions = 0;      // Valid lines replaced by a fill.
  uint64_t cache_dirtied = 0;        // Lines invalidated by Dirty/InvalidateAll/Flush.
  uint64_t cache_write_through = 0;  // Own DMA puts copied into a present line.

  // DMA (the cache's line fills included).
  uint64_t dma_gets = 0;
  uint64_t dma_puts = 0;
  uint64_t dma_get_bytes = 0;
  uint64_t dma_put_bytes = 0;
  uint64_t dma_waits = 0;  // WaitTagMask calls.

  // Atomic unit.
  uint64_t atomic_getllar = 0;
  uint64_t atomic_putllc_success = 0;
  uint64_t atomic_putllc_failure = 0;  // Lost reservation (another SPE wrote the word).
  uint64_t atomic_putlluc = 0;
  uint64_t atomic_loads = 0;

  // Software-managed threads: switches away from a thread that is still alive.
  uint64_t thread_switches = 0;
  uint64_t work_items = 0;  // Items handed out by SpeContext::NextWorkItem.

  // Modeled cycles by cause. Everything but the two waits is the SPU being busy.
  uint64_t compute_cycles = 0;    // Charged by the kernel (SpeContext::AddComputeCycles).
  uint64_t cache_cycles = 0;      // Cache lookups and bookkeeping.
  uint64_t dma_issue_cycles = 0;  // Enqueuing MFC commands.
  uint64_t atomic_cycles = 0;     // Atomic unit operations.
  uint64_t switch_cycles = 0;     // Software thread switches.
  uint64_t dma_stall_cycles = 0;  // Waiting for a transfer that had not completed in model time.
  uint64_t work_wait_cycles = 0;  // Waiting for work a shared index had not published yet.

  // Bumped by the engine itself: its view of what the emulation cannot know.
  uint64_t stale_detections = 0;  // Inconsistent (stale or half-updated) data found and handled.
  uint64_t lock_conflicts = 0;    // Status-word locks lost to another SPE.
  static constexpr int kUserCounters = 8;
  std::array<uint64_t, kUserCounters> user{};  // Free for other engine events.

  uint64_t AtomicOps() const {
    return atomic_getllar + atomic_putllc_success + atomic_putllc_failure + atomic_putlluc +
           atomic_loads;
  }
  uint64_t DmaTransfers() const { return dma_gets + dma_puts; }
  uint64_t DmaBytes() const { return dma_get_bytes + dma_put_bytes; }
  // cache_hits / (cache_hits + cache_misses); 0 when nothing was read.
  double HitRatio() const;
  uint64_t BusyCycles() const {
    return compute_cycles + cache_cycles + dma_issue_cycles + atomic_cycles + switch_cycles;
  }
  // Busy plus waits: the SPE's modeled time over the counted period.
  uint64_t ModeledCycles() const { return BusyCycles() + dma_stall_cycles + work_wait_cycles; }

  void Reset() { *this = SpeCounters(); }
  SpeCounters& operator+=(const SpeCounters& other);
  std::string ToString() const;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_COUNTERS_H_
