#include "cellsim/spe_sort.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <span>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {
namespace {

constexpr size_t kChunkKeys = 512;  // 4 KiB per streaming DMA transfer
constexpr size_t kMaxDmaKeys = DmaEngine::kMaxTransferBytes / sizeof(uint64_t);
// DMA tag groups: two per stream buffer pair, one for the merge-path probes, one per block
// direction.
constexpr unsigned kReadTagA = 0, kReadTagB = 2, kWriteTag = 4, kProbeTag = 6, kBlockGetTag = 7,
                   kBlockPutTag = 8;

size_t RoundUpEven(size_t x) { return (x + 1) & ~size_t{1}; }

// Allocates `keys` 16-byte aligned keys from the SPE's local store; reports an error if full.
uint64_t* LsKeys(SpeContext& spe, size_t keys, const char* what) {
  absl::StatusOr<std::byte*> p = spe.local_store().Allocate(keys * sizeof(uint64_t), 16, what);
  if (!p.ok()) {
    spe.ReportError(p.status());
    return nullptr;
  }
  return reinterpret_cast<uint64_t*>(*p);
}

bool Ok(SpeContext& spe, const absl::StatusOr<uint64_t>& issued) {
  if (!issued.ok()) spe.ReportError(issued.status());
  return issued.ok();
}

// Moves keys [begin, end) of `array` (begin and end even) between it and `ls` in transfers of
// at most 16 KiB, all in tag group `tag`: a get into `ls`, or a put from it.
enum class Dir { kGet, kPut };
bool Transfer(SpeContext& spe, Dir dir, uint64_t* ls, const uint64_t* array, size_t begin,
              size_t end, unsigned tag) {
  for (size_t at = begin; at < end; at += kMaxDmaKeys) {
    const size_t bytes = std::min(kMaxDmaKeys, end - at) * sizeof(uint64_t);
    uint64_t* local = ls + (at - begin);
    if (!Ok(spe, dir == Dir::kGet ? spe.dma().Get(local, Ea(array + at), bytes, tag)
                                  : spe.dma().Put(local, Ea(array + at), bytes, tag)))
      return false;
  }
  return true;
}

// Keys [begin, end) of a main-memory array, read in order through two LS buffers: while one is
// consumed the next chunk is on its way. Chunks start at even positions (DMA wants 16-byte
// aligned addresses), so a stream starting at an odd key skips the one before it.
class KeyReader {
 public:
  KeyReader(SpeContext& spe, const uint64_t* array, size_t begin, size_t end, uint64_t* buffers,
            unsigned tag)
      : spe_(spe), array_(array), pos_(begin), end_(end), buffers_(buffers), tag_(tag) {
    next_fetch_ = begin & ~size_t{1};
    if (pos_ < end_) {
      Fetch(0);
      Fetch(1);
      Switch();
    }
  }
  bool empty() const { return pos_ == end_; }
  uint64_t front() const {
    return buffers_[current_ * kChunkKeys + (pos_ - chunk_begin_[current_])];
  }
  void pop() {
    if (++pos_ < end_ && pos_ == chunk_end_[current_]) {
      Fetch(current_);  // the consumed buffer takes the chunk after the other one's
      current_ ^= 1;
      Switch();
    }
  }

 private:
  void Fetch(int b) {
    chunk_begin_[b] = next_fetch_;
    chunk_end_[b] = std::min(next_fetch_ + kChunkKeys, RoundUpEven(end_));
    if (chunk_begin_[b] < chunk_end_[b] &&
        !Transfer(spe_, Dir::kGet, buffers_ + b * kChunkKeys, array_, chunk_begin_[b],
                  chunk_end_[b], tag_ + b))
      chunk_end_[b] = chunk_begin_[b];
    next_fetch_ = chunk_end_[b];
  }
  // Makes the current buffer usable: waits for its transfer.
  void Switch() {
    if (absl::Status s = spe_.dma().WaitTagMask(1u << (tag_ + current_)); !s.ok())
      spe_.ReportError(s);
    if (chunk_begin_[current_] == chunk_end_[current_]) pos_ = end_;  // a failed transfer
  }

  SpeContext& spe_;
  const uint64_t* array_;
  size_t pos_, end_;
  uint64_t* buffers_;  // 2 x kChunkKeys
  unsigned tag_;
  size_t next_fetch_ = 0;
  size_t chunk_begin_[2] = {0, 0}, chunk_end_[2] = {0, 0};
  int current_ = 0;
};

// Writes keys in order from `begin` (even) through two LS buffers; each full buffer is charged
// its merge work, then put while the other one fills.
class KeyWriter {
 public:
  KeyWriter(SpeContext& spe, uint64_t* array, size_t begin, uint64_t* buffers, unsigned tag)
      : spe_(spe), array_(array), at_(begin), buffers_(buffers), tag_(tag) {}
  void push(uint64_t key, uint64_t cycles) {
    buffers_[current_ * kChunkKeys + filled_++] = key;
    pending_cycles_ += cycles;
    if (filled_ == kChunkKeys) Flush();
  }
  // Puts what is left (an even count: slices end at even positions) and waits for every put.
  void Finish() {
    Flush();
    if (absl::Status s = spe_.dma().WaitTagMask(3u << tag_); !s.ok()) spe_.ReportError(s);
  }

 private:
  void Flush() {
    spe_.AddComputeCycles(pending_cycles_);
    pending_cycles_ = 0;
    if (filled_ == 0) return;
    Transfer(spe_, Dir::kPut, buffers_ + current_ * kChunkKeys, array_, at_, at_ + filled_,
             tag_ + current_);
    at_ += filled_;
    filled_ = 0;
    current_ ^= 1;
    // The buffer about to be refilled is the source of the previous put: it must be done.
    if (absl::Status s = spe_.dma().WaitTagMask(1u << (tag_ + current_)); !s.ok())
      spe_.ReportError(s);
  }

  SpeContext& spe_;
  uint64_t* array_;
  size_t at_;
  uint64_t* buffers_;
  unsigned tag_;
  size_t filled_ = 0;
  uint64_t pending_cycles_ = 0;
  int current_ = 0;
};

// One key of a main-memory array by a 16-byte DMA get (a merge-path probe).
uint64_t ProbeKey(SpeContext& spe, const uint64_t* array, size_t i, uint64_t* ls) {
  if (!Ok(spe, spe.dma().Get(ls, Ea(array + (i & ~size_t{1})), 16, kProbeTag))) return 0;
  if (absl::Status s = spe.dma().WaitTagMask(1u << kProbeTag); !s.ok()) spe.ReportError(s);
  return ls[i & 1];
}

// Sorts blocks of `block` keys of src into dst, SPE by SPE.
void BlockSort(SpeContext& spe, const uint64_t* src, uint64_t* dst, size_t n, size_t block,
               uint64_t merge_cycles, std::atomic<uint64_t>& merged) {
  const size_t blocks = (n + block - 1) / block, spes = size_t(spe.num_spes());
  const size_t first = blocks * spe.index() / spes, last = blocks * (spe.index() + 1) / spes;
  if (first == last) return;
  const LocalStore::Marker mark = spe.local_store().Mark();
  uint64_t* a = LsKeys(spe, block, "sort block");
  uint64_t* b = a ? LsKeys(spe, block, "sort block (merge buffer)") : nullptr;
  uint64_t outputs = 0;
  for (size_t k = first; b != nullptr && k < last; ++k) {
    const size_t begin = k * block, end = std::min(n, begin + block), count = end - begin;
    // The previous block's puts read `a` or `b`: they must be done before it is overwritten.
    if (absl::Status s = spe.dma().WaitTagMask(1u << kBlockPutTag); !s.ok()) spe.ReportError(s);
    if (!Transfer(spe, Dir::kGet, a, src, begin, end, kBlockGetTag)) break;
    if (absl::Status s = spe.dma().WaitTagMask(1u << kBlockGetTag); !s.ok()) spe.ReportError(s);
    uint64_t *from = a, *to = b;
    uint64_t block_outputs = 0;
    for (size_t width = 1; width < count; width *= 2) {
      for (size_t lo = 0; lo < count; lo += 2 * width) {
        const size_t mid = std::min(count, lo + width), hi = std::min(count, lo + 2 * width);
        std::merge(from + lo, from + mid, from + mid, from + hi, to + lo);
      }
      block_outputs += count;
      std::swap(from, to);
    }
    spe.AddComputeCycles(block_outputs * merge_cycles);
    outputs += block_outputs;
    if (!Transfer(spe, Dir::kPut, from, dst, begin, end, kBlockPutTag)) break;
  }
  if (absl::Status s = spe.dma().WaitTagMask(1u << kBlockPutTag); !s.ok()) spe.ReportError(s);
  spe.local_store().Release(mark);
  merged.fetch_add(outputs, std::memory_order_relaxed);
}

// One merge level: runs of `run` keys of src, merged pairwise into dst; this SPE writes its
// slice of the output.
void MergeLevel(SpeContext& spe, const uint64_t* src, uint64_t* dst, size_t n, size_t run,
                uint64_t merge_cycles, std::atomic<uint64_t>& merged,
                std::atomic<uint64_t>& probes) {
  const size_t spes = size_t(spe.num_spes()), i = size_t(spe.index());
  const size_t o0 = (n * i / spes) & ~size_t{1};
  const size_t o1 = i + 1 == spes ? n : (n * (i + 1) / spes) & ~size_t{1};
  if (o0 == o1) return;
  const LocalStore::Marker mark = spe.local_store().Mark();
  uint64_t* buffers = LsKeys(spe, 6 * kChunkKeys + 2, "merge stream buffers");
  if (buffers == nullptr) return;
  uint64_t* probe = buffers + 6 * kChunkKeys;
  KeyWriter out(spe, dst, o0, buffers + 4 * kChunkKeys, kWriteTag);
  uint64_t outputs = 0, probed = 0;
  for (size_t base = o0 - o0 % (2 * run); base < o1; base += 2 * run) {
    const size_t a0 = base, a1 = std::min(n, base + run), b1 = std::min(n, base + 2 * run);
    const size_t na = a1 - a0, nb = b1 - a1;
    const size_t s = std::max(o0, base) - base, e = std::min(o1, b1) - base;
    // Merge path: the first s outputs of this pair are a[0, ia) and b[0, s - ia).
    size_t lo = s > nb ? s - nb : 0, hi = std::min(s, na);
    while (lo < hi) {
      const size_t mid = (lo + hi) / 2;
      const uint64_t am = ProbeKey(spe, src, a0 + mid, probe);
      const uint64_t bj = ProbeKey(spe, src, a1 + (s - mid - 1), probe);
      probed += 2;
      spe.AddComputeCycles(merge_cycles);
      if (am <= bj)
        lo = mid + 1;
      else
        hi = mid;
    }
    const size_t ia = lo, ib = s - lo;
    KeyReader ra(spe, src, a0 + ia, a1, buffers, kReadTagA);
    KeyReader rb(spe, src, a1 + ib, b1, buffers + 2 * kChunkKeys, kReadTagB);
    for (size_t k = s; k < e; ++k) {
      if (!spe.error().ok()) break;
      if (rb.empty() || (!ra.empty() && ra.front() <= rb.front())) {
        out.push(ra.front(), nb == 0 ? 1 : merge_cycles);  // no partner: a copy
        ra.pop();
      } else {
        out.push(rb.front(), merge_cycles);
        rb.pop();
      }
    }
    outputs += e - s;
  }
  out.Finish();
  spe.local_store().Release(mark);
  merged.fetch_add(outputs, std::memory_order_relaxed);
  probes.fetch_add(probed, std::memory_order_relaxed);
}

}  // namespace

absl::StatusOr<SpeSortStats> SortOnSpes(Runtime& runtime, uint64_t* keys, uint64_t* scratch,
                                        size_t n) {
  if (n % 2 != 0)
    return absl::InvalidArgumentError(
        absl::StrFormat("SPE sort: %d keys, need an even count (pad with the largest key)", n));
  if (reinterpret_cast<uintptr_t>(keys) % 16 != 0 || reinterpret_cast<uintptr_t>(scratch) % 16 != 0)
    return absl::InvalidArgumentError("SPE sort: keys and scratch must be 16-byte aligned");
  SpeSortStats stats;
  stats.keys = n;
  if (n == 0) return stats;
  const size_t spes = size_t(runtime.num_spes());
  stats.block_keys =
      std::max<size_t>(2, std::min(kMaxBlockKeys, RoundUpEven((n + spes - 1) / spes)));
  for (size_t runs = (n + stats.block_keys - 1) / stats.block_keys; runs > 1; runs = (runs + 1) / 2)
    ++stats.levels;
  const uint64_t merge_cycles = runtime.spe(0).config().cost.sort_merge_cycles;
  std::atomic<uint64_t> merged{0}, probes{0};
  // The block sort writes where the last level must read from, so the result ends in `keys`.
  uint64_t* from = stats.levels % 2 == 0 ? keys : scratch;
  uint64_t* to = from == keys ? scratch : keys;
  // One SPE program sorts: launched for the block sort, it stays resident through the merge
  // levels, each begun by a wake-up once every SPE has reported the last one done.
  const auto run = [&](const Runtime::Kernel& kernel) -> absl::Status {
    absl::Status s = runtime.Run(kernel, WorkPlan::None(),
                                 stats.runs == 0 ? RunStart::kLaunch : RunStart::kResident);
    ++stats.runs;
    stats.elapsed_cycles += runtime.last_run_cycles();
    return s;
  };
  if (absl::Status s = run([&](SpeContext& spe) {
        BlockSort(spe, keys, from, n, stats.block_keys, merge_cycles, merged);
      });
      !s.ok())
    return s;
  for (size_t width = stats.block_keys; width < n; width *= 2) {
    if (absl::Status s = run([&](SpeContext& spe) {
          MergeLevel(spe, from, to, n, width, merge_cycles, merged, probes);
        });
        !s.ok())
      return s;
    std::swap(from, to);
  }
  stats.merged = merged.load();
  stats.probes = probes.load();
  return stats;
}

}  // namespace femsimp::cellsim
