// A phase's items split over a pool's contexts: each context owns a contiguous share (locality:
// the deterministic rounds hand over their items in vertex order) and takes it in chunks from
// the front; a context done with its own takes chunks from the back of the others', so no
// context waits at the end of the phase while another still has work. Chunks shrink as a share
// runs out (a quarter of what is left, at most `max_chunk`), so the last items are split finely.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace femsimp {

class WorkShares {
 public:
  explicit WorkShares(int contexts)
      : contexts_(contexts), shares_(std::make_unique<Share[]>(contexts)) {}

  // Splits items [0, count) evenly, context c owning the c-th share (count < 2^32: item ids
  // are vertex, face or move numbers). Not concurrent with Next.
  void Reset(size_t count) {
    for (int c = 0; c < contexts_; ++c)
      shares_[c].left.store(uint64_t{count * c / contexts_} << 32 | (count * (c + 1) / contexts_),
                            std::memory_order_relaxed);
  }

  // The next chunk [begin, end) for context c: from the front of its own share, else from the
  // back of another's. False once every share is taken.
  bool Next(int c, size_t max_chunk, size_t* begin, size_t* end) {
    for (int k = 0; k < contexts_; ++k) {
      const int from = (c + k) % contexts_;
      if (Take(shares_[from].left, from == c, max_chunk, begin, end)) return true;
    }
    return false;
  }

 private:
  struct alignas(64) Share {
    std::atomic<uint64_t> left{0};  // what is left of it: front << 32 | back
  };

  static bool Take(std::atomic<uint64_t>& share, bool own, size_t max_chunk, size_t* begin,
                   size_t* end) {
    uint64_t old = share.load(std::memory_order_relaxed);
    for (;;) {
      const size_t front = old >> 32, back = old & 0xffffffffu;
      if (front >= back) return false;
      const size_t chunk = std::clamp<size_t>((back - front) / 4, 1, max_chunk);
      *begin = own ? front : back - chunk;
      *end = own ? front + chunk : back;
      const uint64_t rest = own ? uint64_t{*end} << 32 | back : uint64_t{front} << 32 | *begin;
      if (share.compare_exchange_weak(old, rest, std::memory_order_relaxed)) return true;
    }
  }

  const int contexts_;
  std::unique_ptr<Share[]> shares_;
};

}  // namespace femsimp
