#ifndef FEMSIMP_CELLSIM_SOFTWARE_CACHE_H_
#define FEMSIMP_CELLSIM_SOFTWARE_CACHE_H_

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "cellsim/cost_model.h"
#include "cellsim/cycle_clock.h"
#include "cellsim/dma_engine.h"
#include "cellsim/local_store.h"
#include "cellsim/main_memory.h"
#include "cellsim/spe_hooks.h"

namespace femsimp::cellsim {

struct CacheConfig {
  size_t size_bytes = 64 * 1024;  // Line data only; the tags take LS space on top.
  size_t line_bytes = 128;        // Power of two, 16 .. 16 KiB.
  size_t ways = 4;                // Associativity; LRU within a set.
  // Copy this SPE's own DMA puts into lines it holds, so that it never reads back its own
  // stale writes. Other SPEs' writes are never seen until the line is dirtied.
  bool write_through_own_puts = true;
  unsigned fill_tag = 31;  // DMA tag group of line fills.
};

// A read-only, set-associative software cache over main memory, living in the SPE's local
// store (line data and tags both allocated from it). Reads go through it; writes go around it
// with DMA puts (DmaEngine::Put), as in the paper.
//
// NOT coherent: a line keeps the data it was filled with after another SPE writes main memory,
// until this SPE dirties it (Dirty / InvalidateAll / Flush); the next read then fetches the
// new data. The engine's consistency checks detect stale data and dirty the lines involved.
//
// Timing: a read of a present line costs cache_hit_cycles (and waits for the fill if it is
// still in flight); a miss costs cache_miss_cycles plus a DMA get of the line, and the reader
// waits for it. With several software threads (SpeContext::RunThreads, K > 1) that wait
// suspends the reading thread and lets a ready one run, so reads "transparently yield on a
// miss". Because of that, a pointer returned by Read stays valid only until the calling thread
// next calls into the cache, waits for DMA or yields.
//
// A read must not cross a line boundary (16-byte elements at 16-byte aligned addresses never
// do). Fills are clamped to the registered main-memory region of the address read, so a line
// at the end of an array never reads past it.
class SoftwareCache final : public PutObserver {
 public:
  // Allocates lines and tags from `ls`; fails (ResourceExhausted) when they do not fit, or
  // (InvalidArgument) on a bad geometry.
  static absl::StatusOr<std::unique_ptr<SoftwareCache>> Create(
      const CacheConfig& config, LocalStore* ls, DmaEngine* dma, const MainMemory* memory,
      CycleClock* clock, SpeCounters* counters, const CostModel* cost, Waiter* waiter);

  // Pointer to the `size` bytes at `ea`, in the local store, after any needed fill.
  absl::StatusOr<const std::byte*> Read(uint64_t ea, size_t size);
  // Copies a T (trivially copyable) out of the cache.
  template <typename T>
  absl::StatusOr<T> ReadValue(uint64_t ea) {
    absl::StatusOr<const std::byte*> p = Read(ea, sizeof(T));
    if (!p.ok()) return p.status();
    T value;
    std::memcpy(&value, *p, sizeof(T));
    return value;
  }

  // Starts the fill of the line holding `ea` if absent; never waits.
  absl::Status Touch(uint64_t ea);
  // As Touch, and reports whether the data is already usable: true when the line is present
  // and its fill has completed (a read now would not wait); false when a fill was started or
  // is still in flight. The paper switches software threads only on false.
  absl::StatusOr<bool> TouchReport(uint64_t ea);

  // Invalidates the line holding `ea` (if present) so the next read fetches main memory again.
  void Dirty(uint64_t ea);
  // Invalidates every line.
  void InvalidateAll();
  // Waits for fills in flight, then invalidates every line. The cache holds no written data
  // (writes go by DMA), so there is nothing to write back.
  void Flush();

  bool Contains(uint64_t ea) const;  // Tag lookup only: no counting, no timing.
  const CacheConfig& config() const { return config_; }
  size_t num_sets() const { return num_sets_; }
  size_t tag_bytes() const;  // LS bytes the tags take.

  // PutObserver: write-through of this SPE's own puts (if configured).
  void OnPut(uint64_t ea, const std::byte* data, size_t size) override;

 private:
  // 24 bytes per line, in the local store.
  struct Tag {
    uint64_t line_ea;   // Address of the line (aligned to line_bytes).
    uint64_t ready_at;  // Cycle at which its fill completes.
    uint32_t lru;       // Last use stamp.
    uint16_t lo, hi;    // Valid byte range [lo*16, hi*16) of the line; empty = invalid.
  };

  SoftwareCache(const CacheConfig& config, std::byte* data, Tag* tags, DmaEngine* dma,
                const MainMemory* memory, CycleClock* clock, SpeCounters* counters,
                const CostModel* cost, Waiter* waiter);

  uint64_t LineOf(uint64_t ea) const { return ea & ~(uint64_t{config_.line_bytes} - 1); }
  size_t SetOf(uint64_t line_ea) const { return (line_ea / config_.line_bytes) & (num_sets_ - 1); }
  // The way holding [ea, ea+size), or -1.
  int Lookup(uint64_t ea, size_t size) const;
  // Starts a fill of the line of `ea` into a victim way; returns the way.
  absl::StatusOr<int> Fill(uint64_t ea, size_t size);
  std::byte* LineData(size_t set, int way) const {
    return data_ + (set * config_.ways + way) * config_.line_bytes;
  }
  absl::Status CheckRead(uint64_t ea, size_t size) const;

  CacheConfig config_;
  size_t num_sets_;
  std::byte* data_;
  Tag* tags_;
  DmaEngine* dma_;
  const MainMemory* memory_;
  CycleClock* clock_;
  SpeCounters* counters_;
  const CostModel* cost_;
  Waiter* waiter_;
  uint32_t stamp_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_SOFTWARE_CACHE_H_
