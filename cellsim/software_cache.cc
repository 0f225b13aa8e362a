#include "cellsim/software_cache.h"

#include <algorithm>
#include <memory>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {
namespace {
bool IsPowerOfTwo(size_t v) { return v != 0 && (v & (v - 1)) == 0; }
uint64_t RoundUp16(uint64_t v) { return (v + 15) & ~uint64_t{15}; }
uint64_t RoundDown16(uint64_t v) { return v & ~uint64_t{15}; }
}  // namespace

absl::StatusOr<std::unique_ptr<SoftwareCache>> SoftwareCache::Create(
    const CacheConfig& config, LocalStore* ls, DmaEngine* dma, const MainMemory* memory,
    CycleClock* clock, SpeCounters* counters, const CostModel* cost, Waiter* waiter) {
  if (!IsPowerOfTwo(config.line_bytes) || config.line_bytes < 16 ||
      config.line_bytes > DmaEngine::kMaxTransferBytes) {
    return absl::InvalidArgumentError(
        absl::StrFormat("software cache: line size %d must be a power of two in [16, %d]",
                        config.line_bytes, DmaEngine::kMaxTransferBytes));
  }
  if (config.ways == 0 || config.size_bytes == 0 ||
      config.size_bytes % (config.line_bytes * config.ways) != 0 ||
      !IsPowerOfTwo(config.size_bytes / (config.line_bytes * config.ways))) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "software cache: size %d must be line size %d x ways %d x a power-of-two set count",
        config.size_bytes, config.line_bytes, config.ways));
  }
  if (config.fill_tag >= DmaEngine::kNumTags) {
    return absl::InvalidArgumentError(
        absl::StrFormat("software cache: fill tag %d out of range", config.fill_tag));
  }
  const size_t lines = config.size_bytes / config.line_bytes;
  absl::StatusOr<std::byte*> data =
      ls->Allocate(config.size_bytes, std::min<size_t>(config.line_bytes, 128), "cache lines");
  if (!data.ok()) return data.status();
  absl::StatusOr<std::byte*> tag_mem = ls->Allocate(lines * sizeof(Tag), 16, "cache tags");
  if (!tag_mem.ok()) return tag_mem.status();
  Tag* tags = reinterpret_cast<Tag*>(*tag_mem);
  std::uninitialized_value_construct_n(tags, lines);
  return std::unique_ptr<SoftwareCache>(
      new SoftwareCache(config, *data, tags, dma, memory, clock, counters, cost, waiter));
}

SoftwareCache::SoftwareCache(const CacheConfig& config, std::byte* data, Tag* tags, DmaEngine* dma,
                             const MainMemory* memory, CycleClock* clock, SpeCounters* counters,
                             const CostModel* cost, Waiter* waiter)
    : config_(config),
      num_sets_(config.size_bytes / (config.line_bytes * config.ways)),
      data_(data),
      tags_(tags),
      dma_(dma),
      memory_(memory),
      clock_(clock),
      counters_(counters),
      cost_(cost),
      waiter_(waiter) {}

size_t SoftwareCache::tag_bytes() const { return num_sets_ * config_.ways * sizeof(Tag); }

absl::Status SoftwareCache::CheckRead(uint64_t ea, size_t size) const {
  if (size == 0 || LineOf(ea) != LineOf(ea + size - 1)) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "software cache: read of %d bytes at 0x%x is empty or crosses a %d-byte line", size, ea,
        config_.line_bytes));
  }
  const MainMemory::Region* region = memory_->Find(ea, size);
  // Fills move whole quadwords, so the quadwords holding the read must be inside the region.
  if (region == nullptr || RoundDown16(ea) < RoundUp16(region->begin) ||
      RoundUp16(ea + size) > RoundDown16(region->end)) {
    return absl::OutOfRangeError(absl::StrFormat(
        "software cache: the quadwords of [0x%x, 0x%x) are not inside one registered main "
        "memory region",
        ea, ea + size));
  }
  return absl::OkStatus();
}

int SoftwareCache::Lookup(uint64_t ea, size_t size) const {
  const uint64_t line = LineOf(ea);
  const size_t set = SetOf(line);
  const uint64_t off = ea - line;
  for (size_t w = 0; w < config_.ways; ++w) {
    const Tag& t = tags_[set * config_.ways + w];
    if (t.hi > t.lo && t.line_ea == line && off >= t.lo * 16u && off + size <= t.hi * 16u) {
      return static_cast<int>(w);
    }
  }
  return -1;
}

absl::StatusOr<int> SoftwareCache::Fill(uint64_t ea, size_t size) {
  const uint64_t line = LineOf(ea);
  const size_t set = SetOf(line);
  Tag* ways = &tags_[set * config_.ways];
  const uint64_t now = clock_->Now();
  // Victim: an invalid way, else the LRU line whose fill has completed (so a software thread
  // waiting on a fill keeps it), else the LRU line. A way holding another part of the same
  // line (two registered regions sharing it) is not preferred: taking it over made two
  // threads reading one part each refetch the line in turn forever. Both parts stay, each in
  // its own way, and Lookup finds the one that holds a read.
  int victim = -1;
  for (size_t w = 0; w < config_.ways && victim < 0; ++w) {
    if (ways[w].hi <= ways[w].lo) victim = static_cast<int>(w);
  }
  if (victim < 0) {
    int ready = -1;
    int any = 0;
    for (size_t w = 0; w < config_.ways; ++w) {
      const int wi = static_cast<int>(w);
      if (ways[w].lru < ways[any].lru) any = wi;
      if (ways[w].ready_at <= now && (ready < 0 || ways[w].lru < ways[ready].lru)) ready = wi;
    }
    victim = ready >= 0 ? ready : any;
    ++counters_->cache_evictions;
  }
  const MainMemory::Region* region = memory_->Find(ea, size);
  const uint64_t lo = std::max(line, RoundUp16(region->begin));
  const uint64_t hi = std::min(line + config_.line_bytes, RoundDown16(region->end));
  Tag& t = ways[victim];
  t.hi = t.lo = 0;  // Invalid until the get is issued.
  absl::StatusOr<uint64_t> done =
      dma_->Get(LineData(set, victim) + (lo - line), lo, hi - lo, config_.fill_tag);
  if (!done.ok()) return done.status();
  t.line_ea = line;
  t.ready_at = *done;
  t.lru = ++stamp_;
  t.lo = static_cast<uint16_t>((lo - line) / 16);
  t.hi = static_cast<uint16_t>((hi - line) / 16);
  return victim;
}

absl::StatusOr<const std::byte*> SoftwareCache::Read(uint64_t ea, size_t size) {
  if (absl::Status s = CheckRead(ea, size); !s.ok()) return s;
  ++counters_->cache_reads;
  bool counted = false;
  // Loops because a wait may let another software thread evict the line.
  for (;;) {
    const int way = Lookup(ea, size);
    const uint64_t line = LineOf(ea);
    const size_t set = SetOf(line);
    if (way >= 0) {
      Tag& t = tags_[set * config_.ways + way];
      t.lru = ++stamp_;
      if (!counted) {
        counted = true;
        ++counters_->cache_hits;
        clock_->AddCache(cost_->cache_hit_cycles);
        if (t.ready_at > clock_->Now()) ++counters_->cache_pending_waits;
      }
      if (t.ready_at > clock_->Now()) {
        waiter_->WaitUntil(t.ready_at);
        continue;
      }
      return LineData(set, way) + (ea - line);
    }
    // A miss; also a refetch when the line was evicted while this thread waited.
    counted = true;
    ++counters_->cache_misses;
    clock_->AddCache(cost_->cache_miss_cycles);
    absl::StatusOr<int> filled = Fill(ea, size);
    if (!filled.ok()) return filled.status();
    waiter_->WaitUntil(tags_[set * config_.ways + *filled].ready_at);
  }
}

absl::Status SoftwareCache::Touch(uint64_t ea) { return TouchReport(ea).status(); }

absl::StatusOr<bool> SoftwareCache::TouchReport(uint64_t ea) {
  if (absl::Status s = CheckRead(ea, 1); !s.ok()) return s;
  ++counters_->cache_touches;
  const int way = Lookup(ea, 1);
  if (way >= 0) {
    clock_->AddCache(cost_->cache_hit_cycles);
    return tags_[SetOf(LineOf(ea)) * config_.ways + way].ready_at <= clock_->Now();
  }
  clock_->AddCache(cost_->cache_miss_cycles);
  ++counters_->cache_prefetches;
  absl::StatusOr<int> filled = Fill(ea, 1);
  if (!filled.ok()) return filled.status();
  return false;
}

bool SoftwareCache::Contains(uint64_t ea) const { return Lookup(ea, 1) >= 0; }

void SoftwareCache::Dirty(uint64_t ea) {
  const uint64_t line = LineOf(ea);
  Tag* ways = &tags_[SetOf(line) * config_.ways];
  clock_->AddCache(cost_->cache_hit_cycles);
  for (size_t w = 0; w < config_.ways; ++w) {
    if (ways[w].hi > ways[w].lo && ways[w].line_ea == line) {
      ways[w].lo = ways[w].hi = 0;
      ++counters_->cache_dirtied;
    }
  }
}

void SoftwareCache::InvalidateAll() {
  const size_t lines = num_sets_ * config_.ways;
  for (size_t i = 0; i < lines; ++i) {
    if (tags_[i].hi > tags_[i].lo) {
      tags_[i].lo = tags_[i].hi = 0;
      ++counters_->cache_dirtied;
    }
  }
}

void SoftwareCache::Flush() {
  uint64_t until = 0;
  const size_t lines = num_sets_ * config_.ways;
  for (size_t i = 0; i < lines; ++i) {
    if (tags_[i].hi > tags_[i].lo) until = std::max(until, tags_[i].ready_at);
  }
  waiter_->WaitUntil(until);
  InvalidateAll();
}

void SoftwareCache::OnPut(uint64_t ea, const std::byte* data, size_t size) {
  if (!config_.write_through_own_puts) return;
  const uint64_t end = ea + size;
  for (uint64_t line = LineOf(ea); line < end; line += config_.line_bytes) {
    const size_t set = SetOf(line);
    for (size_t w = 0; w < config_.ways; ++w) {
      Tag& t = tags_[set * config_.ways + w];
      if (t.hi <= t.lo || t.line_ea != line) continue;
      const uint64_t lo = std::max(ea, line + t.lo * 16u);
      const uint64_t hi = std::min(end, line + t.hi * 16u);
      if (lo >= hi) continue;
      std::memcpy(LineData(set, static_cast<int>(w)) + (lo - line), data + (lo - ea), hi - lo);
      ++counters_->cache_write_through;
    }
  }
}

}  // namespace femsimp::cellsim
