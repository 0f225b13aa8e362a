#include "engine/selection.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstring>
#include <utility>

#include "engine/port.h"
#include "engine/quadword.h"
#include "engine/ring.h"

namespace femsimp {
namespace {

// Costs are >= 0, so their float bits order like the values; the vertex id breaks ties, which
// makes the order (and a one-context run) deterministic. With `scatter` (deterministic rounds)
// costs are bucketed to 1/16 of an octave and ties broken by a bijective scramble of the id:
// a smooth cost field orders vertices along its level lines (a torus ring by ring, a plane
// by id), and a round's window of such neighbours would mostly overlap itself.
constexpr uint32_t kScatter = 0x9E3779B1u;  // odd, so multiplying by it is a bijection mod 2^32
constexpr int kBucketDroppedBits = 19;      // of the float's 23 mantissa bits
constexpr uint32_t InverseMod32(uint32_t a) {
  uint32_t x = a;  // Newton's iteration doubles the correct low bits each step
  for (int i = 0; i < 5; ++i) x *= 2u - a * x;
  return x;
}
static_assert(kScatter * InverseMod32(kScatter) == 1u);

uint64_t PackKey(float cost, uint32_t v, bool scatter) {
  uint32_t bits;
  std::memcpy(&bits, &cost, sizeof bits);
  if (scatter) bits &= ~((uint32_t{1} << kBucketDroppedBits) - 1);
  return (uint64_t{bits} << 32) | (scatter ? v * kScatter : v);
}
uint32_t UnpackVertex(uint64_t key, bool scatter) {
  const uint32_t low = static_cast<uint32_t>(key);
  return scatter ? low * InverseMod32(kScatter) : low;
}

constexpr size_t kChunkVertices = 1 << 12;  // at most, between polls of a cancel
constexpr size_t kPrefetchAhead = 4;        // fans read ahead of the one being costed
constexpr uint32_t kAwaitingRetry = kNotRemovable | kRetryBit;

double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

CandidateSelection::CandidateSelection(Mesh& mesh, WorkerPool& pool, const VertexCost& cost,
                                       bool scatter, bool retry_all)
    : mesh_(mesh),
      pool_(pool),
      cost_(cost),
      scatter_(scatter),
      retry_all_(retry_all),
      shares_(pool.size()) {}

std::vector<uint32_t> CandidateSelection::Watched() {
  // A bit per vertex: set for every listed one, then read off word by word, which yields them
  // once each and in vertex order (as a scan reads them: neighbours in memory are read together)
  // without sorting the lists.
  seen_.resize((mesh_.vertex_capacity() + 63) / 64, 0);
  size_t listed = 0;
  for (const std::vector<uint32_t>* from : {&watched_, &requeued_}) {
    for (uint32_t v : *from) seen_[v / 64] |= uint64_t{1} << (v % 64);
    listed += from->size();
  }
  std::vector<uint32_t> list;
  list.reserve(listed);
  for (size_t w = 0; w < seen_.size(); ++w)
    for (uint64_t bits = std::exchange(seen_[w], 0); bits != 0; bits &= bits - 1)
      list.push_back(static_cast<uint32_t>(64 * w + std::countr_zero(bits)));
  return list;
}

std::vector<uint32_t> CandidateSelection::Select(bool reconsider,
                                                 const std::function<bool()>& cancelled,
                                                 double* busy_seconds) {
  const bool scan_all = scan_all_ || retry_all_;
  const std::vector<uint32_t> list = scan_all ? std::vector<uint32_t>{} : Watched();
  const size_t count = scan_all ? mesh_.vertex_capacity() : list.size();
  looked_ = count;
  merged_ = !scan_all;
  const auto vertex = [&](size_t i) { return scan_all ? static_cast<uint32_t>(i) : list[i]; };
  std::atomic<uint32_t>* status = mesh_.status();
  // Only fans that will be read are fetched: most vertices of a late pass are not removable.
  const auto will_read = [&](uint32_t s) {
    return s == kRemovable || (reconsider && (s & kStateMask) == kNotRemovable);
  };

  const int n = pool_.size();
  std::vector<std::vector<uint64_t>> slices(n);
  std::vector<std::vector<uint32_t>> awaiting(n);  // refused, due a retry at a later pass
  std::vector<double> busy(n, 0.0);
  shares_.Reset(count);
  pool_.Run([&](int c) {
    const auto start = std::chrono::steady_clock::now();
    NativePort port(mesh_);
    Ring ring;
    std::vector<uint64_t>& keys = slices[c];
    // Costing time varies along the vertices (only removable ones are costed): contexts share
    // out the work; the keys are merged into one order whoever made them.
    size_t begin, end;
    while (shares_.Next(c, kChunkVertices, &begin, &end)) {
      if (cancelled()) return;
      for (size_t i = begin; i < end; ++i) {
        if (i + kPrefetchAhead < count) {
          const uint32_t ahead = vertex(i + kPrefetchAhead);
          if (will_read(status[ahead].load(std::memory_order_relaxed))) port.PrefetchFan(ahead);
        }
        const uint32_t v = vertex(i);
        uint32_t s = status[v].load(std::memory_order_relaxed);
        if (reconsider && (s & kStateMask) == kNotRemovable && (retry_all_ || (s & kRetryBit))) {
          status[v].store(kRemovable, std::memory_order_relaxed);
          s = kRemovable;
        }
        if (s == kAwaitingRetry) awaiting[c].push_back(v);
        if (s != kRemovable) continue;
        const float c_v = GatherRing(port, v, ring) == RingResult::kOk
                              ? cost_.Cost(ring)
                              : std::numeric_limits<float>::max();
        keys.push_back(PackKey(c_v, v, scatter_));
      }
    }
    std::sort(keys.begin(), keys.end());
    busy[c] = Since(start);
  });
  for (int width = 1; width < n; width *= 2) {
    pool_.Run([&](int c) {
      if (c % (2 * width) != 0 || c + width >= n) return;
      const auto start = std::chrono::steady_clock::now();
      std::vector<uint64_t> merged(slices[c].size() + slices[c + width].size());
      std::merge(slices[c].begin(), slices[c].end(), slices[c + width].begin(),
                 slices[c + width].end(), merged.begin());
      slices[c].swap(merged);
      std::vector<uint64_t>().swap(slices[c + width]);
      busy[c] += Since(start);
    });
  }
  for (double b : busy) *busy_seconds += b;
  std::vector<uint32_t> ids(slices[0].size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = UnpackVertex(slices[0][i], scatter_);

  // What the next selection looks at: these (removed, refused or still removable by then), the
  // refused ones awaiting a retry, and whatever the pass requeues.
  scan_all_ = false;
  requeued_.clear();
  watched_ = ids;
  for (const std::vector<uint32_t>& a : awaiting)
    watched_.insert(watched_.end(), a.begin(), a.end());
  return ids;
}

}  // namespace femsimp
