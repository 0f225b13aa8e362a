#include "cellsim/counters.h"

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {

double SpeCounters::HitRatio() const {
  const uint64_t accesses = cache_hits + cache_misses;
  return accesses == 0 ? 0.0 : static_cast<double>(cache_hits) / accesses;
}

SpeCounters& SpeCounters::operator+=(const SpeCounters& o) {
  cache_reads += o.cache_reads;
  cache_hits += o.cache_hits;
  cache_misses += o.cache_misses;
  cache_touches += o.cache_touches;
  cache_prefetches += o.cache_prefetches;
  cache_pending_waits += o.cache_pending_waits;
  cache_evictions += o.cache_evictions;
  cache_dirtied += o.cache_dirtied;
  cache_write_through += o.cache_write_through;
  dma_gets += o.dma_gets;
  dma_puts += o.dma_puts;
  dma_get_bytes += o.dma_get_bytes;
  dma_put_bytes += o.dma_put_bytes;
  dma_waits += o.dma_waits;
  atomic_getllar += o.atomic_getllar;
  atomic_putllc_success += o.atomic_putllc_success;
  atomic_putllc_failure += o.atomic_putllc_failure;
  atomic_putlluc += o.atomic_putlluc;
  atomic_loads += o.atomic_loads;
  thread_switches += o.thread_switches;
  work_items += o.work_items;
  compute_cycles += o.compute_cycles;
  cache_cycles += o.cache_cycles;
  dma_issue_cycles += o.dma_issue_cycles;
  atomic_cycles += o.atomic_cycles;
  switch_cycles += o.switch_cycles;
  dma_stall_cycles += o.dma_stall_cycles;
  work_wait_cycles += o.work_wait_cycles;
  stale_detections += o.stale_detections;
  lock_conflicts += o.lock_conflicts;
  for (int i = 0; i < kUserCounters; ++i) user[i] += o.user[i];
  return *this;
}

std::string SpeCounters::ToString() const {
  return absl::StrFormat(
      "cache reads=%d hits=%d misses=%d hit_ratio=%.3f prefetches=%d; dma gets=%d puts=%d "
      "bytes=%d; atomics=%d (putllc failures=%d); switches=%d; cycles busy=%d stall=%d "
      "work_wait=%d modeled=%d; stale=%d lock_conflicts=%d",
      cache_reads, cache_hits, cache_misses, HitRatio(), cache_prefetches, dma_gets, dma_puts,
      DmaBytes(), AtomicOps(), atomic_putllc_failure, thread_switches, BusyCycles(),
      dma_stall_cycles, work_wait_cycles, ModeledCycles(), stale_detections, lock_conflicts);
}

}  // namespace femsimp::cellsim
