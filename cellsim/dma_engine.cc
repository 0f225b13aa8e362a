#include "cellsim/dma_engine.h"

#include <algorithm>
#include <atomic>
#include <cstring>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {
namespace {

// Main memory is shared with other SPEs (host threads): relaxed atomic 8-byte accesses keep the
// copy race-free for the C++ memory model (and ThreadSanitizer).
void CopyFromMain(std::byte* ls, uint64_t ea, size_t size) {
  auto* src = reinterpret_cast<uint64_t*>(ea);
  for (size_t i = 0; i < size / 8; ++i) {
    const uint64_t v = std::atomic_ref<uint64_t>(src[i]).load(std::memory_order_relaxed);
    std::memcpy(ls + 8 * i, &v, 8);
  }
}

void CopyToMain(uint64_t ea, const std::byte* ls, size_t size) {
  auto* dst = reinterpret_cast<uint64_t*>(ea);
  for (size_t i = 0; i < size / 8; ++i) {
    uint64_t v;
    std::memcpy(&v, ls + 8 * i, 8);
    std::atomic_ref<uint64_t>(dst[i]).store(v, std::memory_order_relaxed);
  }
}

}  // namespace

absl::Status DmaEngine::Validate(Dir dir, const void* ls, uint64_t ea, size_t size,
                                 unsigned tag) const {
  const char* what = dir == Dir::kGet ? "DMA get" : "DMA put";
  if (tag >= kNumTags) {
    return absl::InvalidArgumentError(
        absl::StrFormat("%s: tag %d out of range [0, %d)", what, tag, kNumTags));
  }
  if (size == 0 || size % 16 != 0 || size > kMaxTransferBytes) {
    return absl::InvalidArgumentError(
        absl::StrFormat("%s: size %d must be a positive multiple of 16 of at most %d bytes", what,
                        size, kMaxTransferBytes));
  }
  if (ea % 16 != 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("%s: effective address 0x%x is not 16-byte aligned", what, ea));
  }
  if (reinterpret_cast<uintptr_t>(ls) % 16 != 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("%s: local store address %p is not 16-byte aligned", what, ls));
  }
  if (!ls_->Contains(ls, size)) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "%s: local store range %p + %d is not inside this SPE's local store", what, ls, size));
  }
  return memory_->Check(ea, size, what);
}

absl::StatusOr<uint64_t> DmaEngine::Issue(Dir dir, void* ls, uint64_t ea, size_t size, unsigned tag,
                                          bool fenced) {
  if (absl::Status s = Validate(dir, ls, ea, size, tag); !s.ok()) return s;
  clock_->AddDmaIssue(cost_->dma_issue_cycles);

  uint64_t start = clock_->Now();
  if (fenced) start = std::max(start, tag_done_[tag]);
  uint64_t& channel_free = dir == Dir::kGet ? get_channel_free_ : put_channel_free_;
  start = std::max(start, channel_free);
  const uint64_t byte_cycles = cost_->ByteCycles(size);
  channel_free = start + byte_cycles;
  const uint64_t done = start + cost_->dma_latency_cycles + byte_cycles;
  tag_done_[tag] = std::max(tag_done_[tag], done);

  auto* bytes = static_cast<std::byte*>(ls);
  if (dir == Dir::kGet) {
    CopyFromMain(bytes, ea, size);
    ++counters_->dma_gets;
    counters_->dma_get_bytes += size;
  } else {
    CopyToMain(ea, bytes, size);
    ++counters_->dma_puts;
    counters_->dma_put_bytes += size;
    if (put_observer_ != nullptr) put_observer_->OnPut(ea, bytes, size);
  }
  return done;
}

absl::Status DmaEngine::WaitTagMask(uint32_t mask) {
  uint64_t until = 0;
  for (unsigned t = 0; t < kNumTags; ++t) {
    if (mask & (1u << t)) until = std::max(until, tag_done_[t]);
  }
  ++counters_->dma_waits;
  waiter_->WaitUntil(until);
  return absl::OkStatus();
}

uint32_t DmaEngine::CompletedTagMask(uint32_t mask) const {
  uint32_t done = 0;
  for (unsigned t = 0; t < kNumTags; ++t) {
    if ((mask & (1u << t)) && tag_done_[t] <= clock_->Now()) done |= 1u << t;
  }
  return done;
}

}  // namespace femsimp::cellsim
