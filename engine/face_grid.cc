#include "engine/face_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace femsimp {
namespace {

// 21 bits per axis: cell coordinates are offset so that they are non-negative.
constexpr int64_t kAxisBits = 21;
constexpr int64_t kAxisLimit = (int64_t{1} << kAxisBits) - 1;

uint64_t Mix(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ULL;
  return k ^ (k >> 33);
}

uint32_t LoadWord(const uint32_t& w) {
  return std::atomic_ref<uint32_t>(const_cast<uint32_t&>(w)).load(std::memory_order_relaxed);
}

// Positions never change during a pass, but the cell back end's DMA puts rewrite a vertex's
// whole quadword (with its `out` word) as atomic stores: read them atomically too.
double LoadCoordinate(const float& c) {
  return std::atomic_ref<float>(const_cast<float&>(c)).load(std::memory_order_relaxed);
}

}  // namespace

FaceGrid::Box FaceGrid::BoxOf(const DVec3* p, int n) {
  Box b{p[0], p[0]};
  for (int i = 1; i < n; ++i) {
    b.lo = {std::min(b.lo.x, p[i].x), std::min(b.lo.y, p[i].y), std::min(b.lo.z, p[i].z)};
    b.hi = {std::max(b.hi.x, p[i].x), std::max(b.hi.y, p[i].y), std::max(b.hi.z, p[i].z)};
  }
  return b;
}

FaceGrid::FaceGrid(const Mesh& mesh) : vertices_(mesh.vertices()), halfedges_(mesh.halfedges()) {
  Rebuild(mesh);
}

double FaceGrid::MeanEdge(const Mesh& mesh, std::vector<uint32_t>* live, DVec3* lo) const {
  double edge_sum = 0.0;
  uint64_t edges = 0;
  *lo = {1e300, 1e300, 1e300};
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (mesh.IsFaceRemoved(f)) continue;
    if (live != nullptr) live->push_back(f);
    const Triangle t = FaceTriangle(f);
    for (int k = 0; k < 3; ++k) {
      edge_sum += Norm(t.p[(k + 1) % 3] - t.p[k]);
      *lo = {std::min(lo->x, t.p[k].x), std::min(lo->y, t.p[k].y), std::min(lo->z, t.p[k].z)};
    }
    edges += 3;
  }
  return edges > 0 && edge_sum > 0 ? edge_sum / double(edges) : 0.5;
}

void FaceGrid::Refresh(const Mesh& mesh) {
  DVec3 lo;
  if (MeanEdge(mesh, nullptr, &lo) > 0.75 * cell_) Rebuild(mesh);
}

void FaceGrid::Rebuild(const Mesh& mesh) {
  // Cells of about twice the mean edge length hold a handful of faces each.
  std::vector<uint32_t> live;
  cell_ = 2.0 * MeanEdge(mesh, &live, &origin_);
  // Large triangles among small ones (a CAD face meshed coarse next to fine fillets) would
  // each cover many cells: coarser cells until the faces cover at most 8 cells each on average.
  uint64_t covered = 0;
  for (;;) {
    covered = 0;
    for (uint32_t f : live) {
      const Triangle t = FaceTriangle(f);
      covered += static_cast<uint64_t>(std::min<int64_t>(RangeOf(BoxOf(t.p, 3)).count(), 1 << 20));
    }
    if (covered <= 8 * live.size() + 64) break;
    cell_ *= 1.5;
  }
  // Faces share cells (a few per cell), and collapses lock the empty cells of their fans' boxes
  // too: a table of as many slots as the faces cover, doubled while a quarter is not free.
  Fill(live, covered);
}

void FaceGrid::Fill(const std::vector<uint32_t>& live, uint64_t min_capacity) {
  for (uint64_t capacity = std::bit_ceil(std::max<uint64_t>(1024, min_capacity));; capacity *= 2) {
    mask_ = capacity - 1;
    cells_ = std::make_unique<Cell[]>(capacity);
    used_.store(0, std::memory_order_relaxed);
    bool fits = true;
    for (uint32_t f : live) {
      const Triangle t = FaceTriangle(f);
      const Box b = BoxOf(t.p, 3);
      fits = fits && Move(f, b, &b);
    }
    if (fits && used_.load(std::memory_order_relaxed) * 2 <= capacity) return;
  }
}

void FaceGrid::EndRound(const Mesh& mesh) {
  deferred_ = false;
  std::sort(pending_.begin(), pending_.end(),
            [](const PendingMove& a, const PendingMove& b) { return a.face < b.face; });
  bool listed = true;
  for (const PendingMove& m : pending_)
    listed = listed && Move(m.face, m.before, m.removed ? nullptr : &m.after);
  pending_.clear();
  if (listed) return;
  std::vector<uint32_t> live;
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f)
    if (!mesh.IsFaceRemoved(f)) live.push_back(f);
  Fill(live, 2 * (mask_ + 1));
}

Triangle FaceGrid::FaceTriangle(uint32_t f) const {
  Triangle t;
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = LoadWord(halfedges_[3 * f + k].target);
    const VertexQ& q = vertices_[v];
    t.id[k] = v;
    t.p[k] = {LoadCoordinate(q.x), LoadCoordinate(q.y), LoadCoordinate(q.z)};
  }
  return t;
}

FaceGrid::Range FaceGrid::RangeOf(const Box& box) const {
  Range r;
  const double lo[3] = {box.lo.x - origin_.x, box.lo.y - origin_.y, box.lo.z - origin_.z};
  const double hi[3] = {box.hi.x - origin_.x, box.hi.y - origin_.y, box.hi.z - origin_.z};
  for (int a = 0; a < 3; ++a) {
    // A point on a cell border belongs to both cells, so touching boxes share a cell.
    r.lo[a] = std::clamp<int64_t>(static_cast<int64_t>(std::floor(lo[a] / cell_)), 0, kAxisLimit);
    r.hi[a] = std::clamp<int64_t>(static_cast<int64_t>(std::floor(hi[a] / cell_)), 0, kAxisLimit);
  }
  return r;
}

uint64_t FaceGrid::Key(int64_t x, int64_t y, int64_t z) const {
  return ((uint64_t(x) << (2 * kAxisBits)) | (uint64_t(y) << kAxisBits) | uint64_t(z)) + 1;
}

bool FaceGrid::Overlaps(uint64_t key, const Box& box) const {
  const uint64_t k = key - 1;
  const int64_t c[3] = {int64_t(k >> (2 * kAxisBits)), int64_t((k >> kAxisBits) & kAxisLimit),
                        int64_t(k & kAxisLimit)};
  const Range r = RangeOf(box);
  for (int a = 0; a < 3; ++a)
    if (c[a] < r.lo[a] || c[a] > r.hi[a]) return false;
  return true;
}

int64_t FaceGrid::Find(uint64_t key) const {
  for (uint64_t i = Mix(key) & mask_, n = 0; n <= mask_; i = (i + 1) & mask_, ++n) {
    const uint64_t k = cells_[i].key.load(std::memory_order_acquire);
    if (k == key) return int64_t(i);
    if (k == kEmpty) return -1;
  }
  return -1;
}

int64_t FaceGrid::Slot(uint64_t key) {
  for (uint64_t i = Mix(key) & mask_, n = 0; n <= mask_; i = (i + 1) & mask_, ++n) {
    uint64_t k = cells_[i].key.load(std::memory_order_acquire);
    if (k == key) return int64_t(i);
    if (k != kEmpty) continue;
    // Keep a quarter of the table free so that probes stay short.
    if (used_.load(std::memory_order_relaxed) * 4 >= 3 * (mask_ + 1)) return -1;
    if (cells_[i].key.compare_exchange_strong(k, key, std::memory_order_acq_rel)) {
      used_.fetch_add(1, std::memory_order_relaxed);
      return int64_t(i);
    }
    if (k == key) return int64_t(i);  // another context claimed it for the same cell
  }
  return -1;
}

FaceGrid::Hold FaceGrid::Acquire(const Box& box, std::vector<uint32_t>* held) {
  const Range r = RangeOf(box);
  if (r.count() > kMaxCellsPerBox) return Hold::kFull;
  if (deferred_) {
    ForEachCell(r, [&](uint64_t key) {
      if (const int64_t slot = Find(key); slot >= 0) held->push_back(static_cast<uint32_t>(slot));
    });
    return Hold::kHeld;
  }
  const size_t first = held->size();
  Hold result = Hold::kHeld;
  ForEachCell(r, [&](uint64_t key) {
    if (result != Hold::kHeld) return;
    const int64_t slot = Slot(key);
    uint32_t expected = 0;
    if (slot < 0) {
      result = Hold::kFull;
    } else if (!cells_[slot].locked.compare_exchange_strong(expected, 1,
                                                            std::memory_order_acquire)) {
      result = Hold::kBusy;
    } else {
      held->push_back(static_cast<uint32_t>(slot));
    }
  });
  if (result != Hold::kHeld) {
    for (size_t i = first; i < held->size(); ++i)
      cells_[(*held)[i]].locked.store(0, std::memory_order_release);
    held->resize(first);
  }
  return result;
}

void FaceGrid::Release(std::vector<uint32_t>* held) {
  if (!deferred_)
    for (uint32_t slot : *held) cells_[slot].locked.store(0, std::memory_order_release);
  held->clear();
}

bool FaceGrid::Move(uint32_t f, const Box& before, const Box* after) {
  if (deferred_) {
    std::lock_guard<std::mutex> lock(pending_mu_);
    pending_.push_back({f, after == nullptr, before, after == nullptr ? before : *after});
    return true;
  }
  ForEachCell(RangeOf(before), [&](uint64_t key) {
    const int64_t slot = Find(key);
    if (slot < 0) return;
    std::vector<uint32_t>& faces = cells_[slot].faces;
    faces.erase(std::remove(faces.begin(), faces.end(), f), faces.end());
  });
  if (after == nullptr) return true;
  // After the build the cells exist: they are held.
  bool listed = true;
  ForEachCell(RangeOf(*after), [&](uint64_t key) {
    const int64_t slot = Slot(key);
    if (slot >= 0) {
      cells_[slot].faces.push_back(f);
    } else {
      listed = false;
    }
  });
  return listed;
}

}  // namespace femsimp
