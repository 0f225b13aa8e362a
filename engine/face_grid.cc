#include "engine/face_grid.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>

namespace femsimp {
namespace {

// Each thread's shard of a round's moves: threads numbered as they first record one, so that a
// pool's few threads land in different shards.
size_t ThreadShard() {
  static std::atomic<size_t> next{0};
  thread_local const size_t shard = next.fetch_add(1, std::memory_order_relaxed);
  return shard;
}

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

// Holds a cell's lock (when given one) for one change of its list, spinning meanwhile: changes
// are short, and only contexts sharing a round's moves meet.
class SpinHold {
 public:
  explicit SpinHold(std::atomic<uint32_t>* lock) : lock_(lock) {
    if (lock_ == nullptr) return;
    for (uint32_t free = 0; !lock_->compare_exchange_weak(free, 1, std::memory_order_acquire);
         free = 0)
      SpinPause();
  }
  ~SpinHold() {
    if (lock_ != nullptr) lock_->store(0, std::memory_order_release);
  }
  SpinHold(const SpinHold&) = delete;
  SpinHold& operator=(const SpinHold&) = delete;

 private:
  std::atomic<uint32_t>* lock_;
};

}  // namespace

FaceGrid::Box FaceGrid::BoxOf(const DVec3* p, int n) {
  Box b{p[0], p[0]};
  for (int i = 1; i < n; ++i) {
    b.lo = {std::min(b.lo.x, p[i].x), std::min(b.lo.y, p[i].y), std::min(b.lo.z, p[i].z)};
    b.hi = {std::max(b.hi.x, p[i].x), std::max(b.hi.y, p[i].y), std::max(b.hi.z, p[i].z)};
  }
  return b;
}

FaceGrid::FaceGrid(const Mesh& mesh, const std::function<bool()>& cancelled, WorkerPool* pool)
    : vertices_(mesh.vertices()),
      halfedges_(mesh.halfedges()),
      point_ids_(mesh.point_ids()),
      pool_(pool) {
  Rebuild(mesh, cancelled);
}

template <class Body>
bool FaceGrid::ForEachChunk(size_t count, const std::function<bool()>& cancelled,
                            Body&& body) const {
  const size_t chunks = (count + kPollFaces - 1) / kPollFaces;
  const int n = pool_ == nullptr || chunks < 2 ? 1 : pool_->size();
  std::atomic<bool> stopped{false};
  const auto run = [&](int c) {
    for (size_t k = size_t(c); k < chunks && !stopped.load(std::memory_order_relaxed); k += n) {
      if (cancelled && cancelled()) {
        stopped.store(true, std::memory_order_relaxed);
        return;
      }
      body(k, k * kPollFaces, std::min<size_t>(count, (k + 1) * kPollFaces));
    }
  };
  if (n == 1)
    run(0);
  else
    pool_->Run(run);
  return !stopped.load();
}

double FaceGrid::MeanEdge(const Mesh& mesh, std::vector<uint32_t>* live, DVec3* lo) {
  struct Part {
    double edge_sum = 0.0, magnitude = 0.0;
    DVec3 lo{1e300, 1e300, 1e300};
    std::vector<uint32_t> live;
  };
  std::vector<Part> parts((mesh.face_capacity() + kPollFaces - 1) / kPollFaces);
  ForEachChunk(mesh.face_capacity(), {}, [&](size_t k, size_t begin, size_t end) {
    Part& part = parts[k];
    for (size_t f = begin; f < end; ++f) {
      if (mesh.IsFaceRemoved(uint32_t(f))) continue;
      part.live.push_back(uint32_t(f));
      const Triangle t = FaceTriangle(uint32_t(f));
      for (int c = 0; c < 3; ++c) {
        part.edge_sum += Norm(t.p[(c + 1) % 3] - t.p[c]);
        part.lo = {std::min(part.lo.x, t.p[c].x), std::min(part.lo.y, t.p[c].y),
                   std::min(part.lo.z, t.p[c].z)};
        part.magnitude = std::max(
            {part.magnitude, std::fabs(t.p[c].x), std::fabs(t.p[c].y), std::fabs(t.p[c].z)});
      }
    }
  });
  // Summed chunk by chunk in order: the same mean for any number of contexts.
  double edge_sum = 0.0, magnitude = 0.0;
  uint64_t faces = 0;
  *lo = {1e300, 1e300, 1e300};
  for (Part& part : parts) {
    edge_sum += part.edge_sum;
    magnitude = std::max(magnitude, part.magnitude);
    *lo = {std::min(lo->x, part.lo.x), std::min(lo->y, part.lo.y), std::min(lo->z, part.lo.z)};
    faces += part.live.size();
    if (live != nullptr) live->insert(live->end(), part.live.begin(), part.live.end());
  }
  magnitude_ = magnitude;
  tracked_length_.store(edge_sum, std::memory_order_relaxed);
  tracked_faces_.store(static_cast<int64_t>(faces), std::memory_order_relaxed);
  return faces > 0 && edge_sum > 0 ? edge_sum / double(3 * faces) : 0.5;
}

void FaceGrid::Track(double length_change, int64_t face_change) {
  tracked_length_.fetch_add(length_change, std::memory_order_relaxed);
  tracked_faces_.fetch_add(face_change, std::memory_order_relaxed);
}

void FaceGrid::Refresh(const Mesh& mesh, const std::function<bool()>& cancelled) {
  // The tracked mean differs from the measured one by rounding only (below 1e-6 relative even
  // for a billion faces): the mesh is measured only when the mean may reach the threshold.
  const double length = tracked_length_.load(std::memory_order_relaxed);
  const int64_t faces = tracked_faces_.load(std::memory_order_relaxed);
  // Collapses in the free schedule claim the empty cells of their boxes as they go.
  const bool crowded = used_.load(std::memory_order_relaxed) * 2 > mask_ + 1;
  if (!crowded && faces > 0 && length > 0 &&
      length / (3.0 * double(faces)) < 0.75 * cell_ * (1 - 1e-4))
    return;
  DVec3 lo;
  if (crowded || MeanEdge(mesh, nullptr, &lo) > 0.75 * cell_) Rebuild(mesh, cancelled);
}

void FaceGrid::Rebuild(const Mesh& mesh, const std::function<bool()>& cancelled) {
  // Cells of about twice the mean edge length hold a handful of faces each.
  std::vector<uint32_t> live;
  cell_ = 2.0 * MeanEdge(mesh, &live, &origin_);
  // Large triangles among small ones (a CAD face meshed coarse next to fine fillets) would
  // each cover many cells: coarser cells until the faces cover at most 8 cells each on average.
  uint64_t covered = 0;
  for (;;) {
    std::atomic<uint64_t> sum{0};
    const bool done = ForEachChunk(live.size(), cancelled, [&](size_t, size_t begin, size_t end) {
      uint64_t part = 0;
      for (size_t i = begin; i < end; ++i) {
        const Triangle t = FaceTriangle(live[i]);
        part += static_cast<uint64_t>(std::min<int64_t>(RangeOf(BoxOf(t.p, 3)).count(), 1 << 20));
      }
      sum.fetch_add(part, std::memory_order_relaxed);
    });
    if (!done) return;
    covered = sum.load();
    if (covered <= 8 * live.size() + 64) break;
    cell_ *= 1.5;
  }
  // Faces share cells (a handful to a few dozen listings a cell): a first guess at the table.
  Fill(live, covered / 8, cancelled);
}

void FaceGrid::Fill(const std::vector<uint32_t>& live, uint64_t min_capacity,
                    const std::function<bool()>& cancelled) {
  for (uint64_t capacity = std::bit_ceil(std::max<uint64_t>(1024, min_capacity));;) {
    mask_ = capacity - 1;
    cells_ = MakeHugePageArray<Cell>(capacity);
    used_.store(0, std::memory_order_relaxed);
    // Pass 1: claim the cells and count their listings (cells are claimed by compare-and-swap,
    // so contexts may claim them together; where each lands does not matter).
    std::atomic<bool> fits{true};
    const bool done = ForEachChunk(live.size(), cancelled, [&](size_t, size_t begin, size_t end) {
      for (size_t i = begin; i < end && fits.load(std::memory_order_relaxed); ++i) {
        const Triangle t = FaceTriangle(live[i]);
        ForEachCell(RangeOf(BoxOf(t.p, 3)), [&](uint64_t key) {
          const int64_t slot = Slot(key);
          if (slot < 0) {
            fits.store(false, std::memory_order_relaxed);
            return;
          }
          std::atomic_ref<uint32_t>(cells_[slot].size).fetch_add(1, std::memory_order_relaxed);
        });
      }
    });
    if (!done) return;
    // Collapses also claim the empty cells of their fans' boxes: at most a quarter full now.
    const uint64_t used = used_.load(std::memory_order_relaxed);
    if (!fits.load() || 4 * used > capacity) {
      capacity = std::max(2 * capacity, std::bit_ceil(4 * used));
      continue;
    }
    // Pass 2: every cell a slice of one array, with room to grow by a quarter (beyond that it
    // moves to an array of its own): one allocation, not one or more per cell.
    const auto slice = [](uint32_t n) { return n == 0 ? 0 : n + n / 4 + 1; };
    uint64_t total = 0;
    for (uint64_t c = 0; c < capacity; ++c) total += slice(cells_[c].size);
    arena_ = MakeHugePageArrayForOverwrite<Listing>(total);
    Listing* next = arena_.get();
    for (uint64_t c = 0; c < capacity; ++c) {
      Cell& cell = cells_[c];
      cell.data = next;
      cell.capacity = slice(cell.size);
      next += cell.capacity;
      cell.size = 0;
    }
    // Pass 3: list the faces. A cell's listings come in whatever order the contexts reach it:
    // no reader depends on that order (a face comes from the first held cell its listing's
    // corner says, and the intersection check keeps the smallest face id it meets). The cells
    // are found again by their keys: pass 1 keeping each listing's slot for this pass cost more
    // (its memory, a fresh page fault per 1,024 listings, copies as it grew) than the lookups.
    ForEachChunk(live.size(), cancelled, [&](size_t, size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        const Triangle t = FaceTriangle(live[i]);
        const Span span = SpanOf(BoxOf(t.p, 3));
        const Range& r = span.range;
        for (int64_t x = r.lo[0]; x <= r.hi[0]; ++x)
          for (int64_t y = r.lo[1]; y <= r.hi[1]; ++y)
            for (int64_t z = r.lo[2]; z <= r.hi[2]; ++z) {
              Cell& cell = cells_[Find(Key(x, y, z))];
              const uint32_t at =
                  std::atomic_ref<uint32_t>(cell.size).fetch_add(1, std::memory_order_relaxed);
              cell.data[at] = ListingIn(live[i], span, x, y, z);
            }
      }
    });
    return;
  }
}

void FaceGrid::Append(Cell& cell, const Listing& listing) {
  if (cell.size == cell.capacity) {
    const uint32_t capacity = std::max<uint32_t>(4, 2 * cell.capacity);
    std::unique_ptr<Listing[]> grown = std::make_unique_for_overwrite<Listing[]>(capacity);
    std::copy_n(cell.data, cell.size, grown.get());
    cell.grown = std::move(grown);
    cell.data = cell.grown.get();
    cell.capacity = capacity;
  }
  cell.data[cell.size++] = listing;
}

std::vector<uint32_t> FaceGrid::LiveFaces(const Mesh& mesh) {
  std::vector<uint32_t> live;
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f)
    if (!mesh.IsFaceRemoved(f)) live.push_back(f);
  return live;
}

void FaceGrid::BeginRound(const Mesh& mesh, uint64_t new_cells) {
  // Slot refuses a new cell once three quarters of the table are used.
  const uint64_t needed = used_.load(std::memory_order_relaxed) + new_cells;
  if (4 * needed >= 3 * (mask_ + 1)) Fill(LiveFaces(mesh), std::bit_ceil(2 * needed), {});
  deferred_ = true;
}

void FaceGrid::EndRound(const Mesh& mesh) {
  ApplyMoves(0, MovesOfRound(), /*shared=*/false);
  FinishRound(mesh);
}

size_t FaceGrid::MovesOfRound() {
  deferred_ = false;
  unlisted_.store(false, std::memory_order_relaxed);
  shard_start_[0] = 0;
  for (size_t k = 0; k < kPendingShards; ++k)
    shard_start_[k + 1] = shard_start_[k] + shards_[k].moves.size();
  return shard_start_[kPendingShards];
}

void FaceGrid::ApplyMoves(size_t begin, size_t end, bool shared) {
  size_t k =
      std::upper_bound(shard_start_.begin(), shard_start_.end(), begin) - shard_start_.begin() - 1;
  bool listed = true;
  for (size_t i = begin; i < end; ++i) {
    while (i >= shard_start_[k + 1]) ++k;
    const FaceMove& m = shards_[k].moves[i - shard_start_[k]];
    ForEachCellOp(m.face, m.before, m.removed ? nullptr : &m.after,
                  [&](const CellOp& op) { listed = Apply(op, shared) && listed; });
  }
  if (!listed) unlisted_.store(true, std::memory_order_relaxed);
}

void FaceGrid::FinishRound(const Mesh& mesh) {
  for (PendingShard& shard : shards_) shard.moves.clear();
  TrackShards();  // before a new index measures the mesh anew
  if (unlisted_.load(std::memory_order_relaxed)) Fill(LiveFaces(mesh), 2 * (mask_ + 1), {});
}

Triangle FaceGrid::FaceTriangle(uint32_t f) const {
  Triangle t;
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = LoadWord(halfedges_[3 * f + k].target);
    const VertexQ& q = vertices_[v];
    t.id[k] = PointId(v);
    t.p[k] = {LoadCoordinate(q.x), LoadCoordinate(q.y), LoadCoordinate(q.z)};
  }
  return t;
}

void FaceGrid::PrefetchCorners(uint32_t f) const {
  for (int k = 0; k < 3; ++k)
    __builtin_prefetch(&vertices_[LoadWord(halfedges_[3 * f + k].target)]);
}

FaceGrid::Span FaceGrid::SpanOf(const Box& box) const {
  Span s;
  const double lo[3] = {box.lo.x - origin_.x, box.lo.y - origin_.y, box.lo.z - origin_.z};
  const double hi[3] = {box.hi.x - origin_.x, box.hi.y - origin_.y, box.hi.z - origin_.z};
  // Far beyond the cells' coordinates, so that the clamp below changes no cell.
  constexpr double kFar = double(int64_t{1} << 40);
  constexpr double kSteps = double(1 << kListingBits);
  for (int a = 0; a < 3; ++a) {
    // Scaling by a power of two is exact, so the floor of the units over the steps (an
    // arithmetic shift floors) is the floor of the coordinate in cells.
    const double lo_units = std::min(std::max(lo[a] / cell_ * kSteps, -kFar), kFar);
    const double hi_units = std::min(std::max(hi[a] / cell_ * kSteps, -kFar), kFar);
    s.lo[a] = Floor(lo_units);
    s.hi[a] = Ceil(hi_units);
    // A point on a cell border belongs to both cells, so touching boxes share a cell.
    s.range.lo[a] = std::clamp<int64_t>(s.lo[a] >> kListingBits, 0, kAxisLimit);
    s.range.hi[a] = std::clamp<int64_t>(Floor(hi_units) >> kListingBits, 0, kAxisLimit);
  }
  return s;
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

// A fan's box covers a few cells; a larger one is not worth the hints.
constexpr int64_t kMaxPrefetchCells = 8;

void FaceGrid::PrefetchSlots(const Box& box) const {
  const Range r = RangeOf(box);
  if (r.count() > kMaxPrefetchCells) return;
  ForEachCell(r, [&](uint64_t key) { __builtin_prefetch(&cells_[Mix(key) & mask_]); });
}

void FaceGrid::PrefetchLists(const Box& box) const {
  const Range r = RangeOf(box);
  if (r.count() > kMaxPrefetchCells) return;
  ForEachCell(r, [&](uint64_t key) {
    const int64_t slot = Find(key);
    if (slot < 0) return;
    const Cell& cell = cells_[slot];
    // The first two lines: a cell lists a handful of faces, 16 bytes each.
    if (cell.size > 0) __builtin_prefetch(cell.data);
    if (cell.size > 4) __builtin_prefetch(cell.data + 4);
  });
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
  const size_t first = held->size();
  Hold result = Hold::kHeld;
  ForEachCell(r, [&](uint64_t key) {
    if (result != Hold::kHeld) return;
    const int64_t slot = Slot(key);
    uint32_t expected = 0;
    if (slot < 0) {
      result = Hold::kFull;
    } else if (deferred_) {
      held->push_back(static_cast<uint32_t>(slot));
    } else if (!cells_[slot].locked.compare_exchange_strong(expected, 1,
                                                            std::memory_order_acquire)) {
      result = Hold::kBusy;
    } else {
      held->push_back(static_cast<uint32_t>(slot));
    }
  });
  if (result != Hold::kHeld) {
    for (size_t i = first; i < held->size() && !deferred_; ++i)
      cells_[(*held)[i]].locked.store(0, std::memory_order_release);
    held->resize(first);
    return result;
  }
  // The holder reads the cells' lists next: fetch them all at once rather than one by one.
  for (size_t i = first; i < held->size(); ++i) __builtin_prefetch(cells_[(*held)[i]].data);
  return result;
}

void FaceGrid::Release(std::vector<uint32_t>* held) {
  if (!deferred_)
    for (uint32_t slot : *held) cells_[slot].locked.store(0, std::memory_order_release);
  held->clear();
}

FaceGrid::Listing FaceGrid::ListingIn(uint32_t f, const Span& s, int64_t x, int64_t y, int64_t z) {
  Listing l{f, {}, {}};
  const int64_t c[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    l.lo[a] = Relative(s.lo[a], c[a]);
    l.hi[a] = Relative(s.hi[a], c[a]);
    // Already so (the origin is the mesh's lower corner), but the visit relies on it.
    l.lo[a] =
        c[a] == s.range.lo[a] ? std::max<int16_t>(l.lo[a], 0) : std::min<int16_t>(l.lo[a], -1);
  }
  return l;
}

bool FaceGrid::Move(uint32_t f, const Box& before, const Box* after) {
  const FaceMove move{f, after == nullptr, before, after == nullptr ? before : *after};
  return CommitMoves({&move, 1}, 0.0, 0);
}

bool FaceGrid::CommitMoves(std::span<const FaceMove> moves, double length_change,
                           int64_t face_change) {
  if (deferred_) {
    PendingShard& shard = shards_[ThreadShard() % kPendingShards];
    std::lock_guard<std::mutex> lock(shard.mu);
    shard.moves.insert(shard.moves.end(), moves.begin(), moves.end());
    shard.length_change += length_change;
    shard.face_change += face_change;
    return true;
  }
  bool listed = true;
  for (const FaceMove& m : moves)
    ForEachCellOp(m.face, m.before, m.removed ? nullptr : &m.after,
                  [&](const CellOp& op) { listed = Apply(op) && listed; });
  if (length_change != 0.0 || face_change != 0) Track(length_change, face_change);
  return listed;
}

void FaceGrid::TrackShards() {
  for (PendingShard& shard : shards_) {
    if (shard.length_change != 0.0 || shard.face_change != 0)
      Track(shard.length_change, shard.face_change);
    shard.length_change = 0.0;
    shard.face_change = 0;
  }
}

template <class Emit>
void FaceGrid::ForEachCellOp(uint32_t f, const Box& before, const Box* after, Emit&& emit) const {
  // A face keeps most of its cells when a corner moves: it leaves some, enters some, and its
  // listing is rewritten in the rest (list order does not matter).
  const Range from = RangeOf(before);
  Span span;
  if (after != nullptr) {
    span = SpanOf(*after);
  } else {
    span.range = Range{{1, 1, 1}, {0, 0, 0}};  // no cells
  }
  const Range& to = span.range;
  const auto in = [](const Range& r, int64_t x, int64_t y, int64_t z) {
    return r.lo[0] <= x && x <= r.hi[0] && r.lo[1] <= y && y <= r.hi[1] && r.lo[2] <= z &&
           z <= r.hi[2];
  };
  for (int64_t x = from.lo[0]; x <= from.hi[0]; ++x)
    for (int64_t y = from.lo[1]; y <= from.hi[1]; ++y)
      for (int64_t z = from.lo[2]; z <= from.hi[2]; ++z) {
        if (in(to, x, y, z))
          emit(CellOp{Key(x, y, z), ListingIn(f, span, x, y, z), CellOp::kRelist});
        else
          emit(CellOp{Key(x, y, z), Listing{f, {}, {}}, CellOp::kDrop});
      }
  for (int64_t x = to.lo[0]; x <= to.hi[0]; ++x)
    for (int64_t y = to.lo[1]; y <= to.hi[1]; ++y)
      for (int64_t z = to.lo[2]; z <= to.hi[2]; ++z)
        if (!in(from, x, y, z))
          emit(CellOp{Key(x, y, z), ListingIn(f, span, x, y, z), CellOp::kAdd});
}

bool FaceGrid::Apply(const CellOp& op, bool lock) {
  if (op.kind != CellOp::kAdd) {
    const int64_t slot = Find(op.key);
    if (slot >= 0) {
      Cell& cell = cells_[slot];
      const SpinHold hold(lock ? &cell.locked : nullptr);
      const uint32_t f = op.listing.face;
      Listing* it = std::find_if(cell.data, cell.data + cell.size,
                                 [f](const Listing& l) { return l.face == f; });
      if (it != cell.data + cell.size) {
        if (op.kind == CellOp::kRelist)
          *it = op.listing;
        else
          *it = cell.data[--cell.size];
        return true;
      }
    }
    if (op.kind == CellOp::kDrop) return true;
  }
  // After the build the cells exist: they are held.
  const int64_t slot = Slot(op.key);
  if (slot < 0) return false;
  const SpinHold hold(lock ? &cells_[slot].locked : nullptr);
  Append(cells_[slot], op.listing);
  return true;
}

}  // namespace femsimp
