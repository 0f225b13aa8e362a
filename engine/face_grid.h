// A spatial index of the mesh's faces for the self-intersection rule: a hashed uniform grid whose
// cells list the faces whose bounding boxes they overlap, with one try-lock per cell.
//
// Locking argument (the same shape as the paper's for vertices). A collapse of V holds the
// cells that overlap the bounding box of V's fan (V and its one-ring) from before it checks
// until after its writes are visible. Every face it writes lies in that box before and after
// (the new triangles use fan vertices only), so it writes only faces and cell lists inside
// cells it holds. It reads only cells it holds, and only faces listed there; a face being
// rewritten by another collapse is listed in cells that collapse holds, so it cannot be read
// meanwhile. Two collapses whose new triangles could meet overlap in a cell, so they cannot
// both hold their cells: one gives its candidate up as a lock conflict.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "engine/huge_page_allocator.h"
#include "engine/mesh.h"
#include "engine/triangle_intersection.h"
#include "engine/vec.h"
#include "engine/worker_pool.h"

namespace femsimp {

class FaceGrid {
 public:
  // Indexes the live faces of `mesh`, which must outlive the grid. Indexing a few million faces
  // takes a while: `cancelled` (thread-safe, may be empty) is polled every kPollFaces faces,
  // and once it says true the grid stops half built and must not be used (a cancel stays
  // true: the caller sees it and ends the run).
  // With a pool, indexing runs on its contexts (then, and on every re-index later: the caller
  // must not be running the pool meanwhile); the index is the same for any number of them.
  explicit FaceGrid(const Mesh& mesh, const std::function<bool()>& cancelled = {},
                    WorkerPool* pool = nullptr);
  // Between passes (nothing held): indexes the mesh anew when its faces have grown well past
  // the cells (as the mesh coarsens), so that a fan still covers a few cells. It measures the
  // mesh only when the edge lengths its users report (Track) say it may have to. Polls
  // `cancelled` as the constructor does.
  void Refresh(const Mesh& mesh, const std::function<bool()>& cancelled = {});
  // What a commit changed: the sum over the live faces of their three edge lengths, and their
  // number.
  void Track(double length_change, int64_t face_change);

  struct Box {
    DVec3 lo, hi;
  };
  static Box BoxOf(const DVec3* points, int n);

  enum class Hold { kHeld, kBusy, kFull };
  // Locks every cell that overlaps `box`, appending their slots to *held. kBusy: another
  // context holds one (nothing stays locked); kFull: the box spans too many cells, or the table
  // of cells is full (the rule then refuses the collapse: it cannot prove it safe).
  Hold Acquire(const Box& box, std::vector<uint32_t>* held);
  void Release(std::vector<uint32_t>* held);

  // Deterministic rounds (engine/rounds.h): the collapses of a round have disjoint fan boxes,
  // so they need no cell locks, and the lists stay as they were at the round's start while
  // they run: Acquire finds (or creates) the cells without locking them, Release forgets them,
  // and Move is recorded. A round never finds the table full (that would make refusals depend
  // on timing): BeginRound first grows it if the round's boxes, `new_cells` cells at most
  // (CellsOf summed over them), might fill it. EndRound applies the moves (a face moves at most
  // once a round, so they commute) and indexes the mesh anew if a moved face found no room: the
  // set of cells, hence whether there is room, does not depend on the order, nor the index on
  // the number of contexts (a cell's list order may, and no reader depends on it).
  void BeginRound(const Mesh& mesh, uint64_t new_cells);
  void EndRound(const Mesh& mesh);
  // EndRound in steps, so that several contexts can share the moves (the rounds do so beside
  // the next round's fan reads): MovesOfRound (one thread) ends the round and counts its moves;
  // ApplyMoves (any contexts at once, on disjoint ranges of [0, count)) applies them, each cell
  // under its lock when `shared`; FinishRound (one thread, once all are applied) indexes anew
  // if needed.
  size_t MovesOfRound();
  void ApplyMoves(size_t begin, size_t end, bool shared);
  void FinishRound(const Mesh& mesh);
  // The cells Acquire(box) would claim at most.
  uint64_t CellsOf(const Box& box) const {
    return static_cast<uint64_t>(std::min<int64_t>(RangeOf(box).count(), kMaxCellsPerBox));
  }
  // A cancelled run ends in the middle of a round: the recorded moves are dropped (applying
  // them would only delay the end), and the index no longer matches the mesh.
  void AbandonRound() {
    deferred_ = false;
    for (PendingShard& shard : shards_) shard.moves.clear();
    TrackShards();
  }

  // Calls visit(face) for every face listed in the held cells that overlap `box` (a face may
  // come more than once); stops early when visit returns false.
  template <class Visit>
  void ForEachFace(const Box& box, const std::vector<uint32_t>& held, Visit&& visit) const {
    for (uint32_t slot : held) {
      if (!Overlaps(cells_[slot].key.load(std::memory_order_relaxed), box)) continue;
      for (const Listing& l : cells_[slot].list())
        if (!visit(l.face)) return;
    }
  }

  // Calls visit(face) once for every face listed in the cells that Acquire(box, held) locked
  // (`held` as it left it) whose box may overlap `near`: every face whose box overlaps it comes,
  // and a few more (the cells keep the boxes rounded outwards). No sort and no lookup: the
  // cells' lists are read in order, and a face comes from the first held cell it is listed in.
  template <class Visit>
  void ForEachFaceNear(const Box& box, const std::vector<uint32_t>& held, const Box& near,
                       Visit&& visit) const {
    const Range r = RangeOf(box);
    const Span n = SpanOf(near);
    const uint32_t* slot = held.data();
    int16_t lo[3], hi[3];  // `near` in the units of the cell's listings
    for (int64_t x = r.lo[0]; x <= r.hi[0]; ++x) {
      lo[0] = Relative(n.lo[0], x);
      hi[0] = Relative(n.hi[0], x);
      for (int64_t y = r.lo[1]; y <= r.hi[1]; ++y) {
        lo[1] = Relative(n.lo[1], y);
        hi[1] = Relative(n.hi[1], y);
        for (int64_t z = r.lo[2]; z <= r.hi[2]; ++z, ++slot) {
          lo[2] = Relative(n.lo[2], z);
          hi[2] = Relative(n.hi[2], z);
          // A listing's lo is negative on an axis iff the face's cells begin before this cell:
          // the first held cell of the face's cells begins them, or begins the held block.
          const bool first[3] = {x == r.lo[0], y == r.lo[1], z == r.lo[2]};
          for (const Listing& l : cells_[*slot].list()) {
            if (l.lo[0] > hi[0] || l.hi[0] < lo[0] || l.lo[1] > hi[1] || l.hi[1] < lo[1] ||
                l.lo[2] > hi[2] || l.hi[2] < lo[2])
              continue;
            if ((l.lo[0] >= 0 || first[0]) && (l.lo[1] >= 0 || first[1]) &&
                (l.lo[2] >= 0 || first[2]))
              visit(l.face);
          }
        }
      }
    }
  }

  // The corners of face f as they are in the mesh now (f must be in a held cell), with their
  // point ids as the corners' ids.
  Triangle FaceTriangle(uint32_t f) const;
  // Vertex v's point (Mesh::point_ids): copies of one point share it.
  uint32_t PointId(uint32_t v) const { return point_ids_ == nullptr ? v : point_ids_[v]; }
  // Hints that FaceTriangle(f) comes soon: its half-edges, or (once those are at hand) its
  // corners' vertices.
  void Prefetch(uint32_t f) const {
    __builtin_prefetch(&halfedges_[3 * f]);
    __builtin_prefetch(&halfedges_[3 * f + 2]);  // 48 bytes may span two cache lines
  }
  void PrefetchCorners(uint32_t f) const;
  // Hints that a hold of `box` comes soon, in two stages some candidates apart: the slots its
  // cells hash to, then (those at hand) the cells' lists. Only while the lists stay as they
  // are (a deterministic round's removals): the second stage reads them unlocked.
  void PrefetchSlots(const Box& box) const;
  void PrefetchLists(const Box& box) const;

  // Moves face f in the index from the cells of `before` to those of `after` (both within held
  // cells); an empty `after` removes it. False when a cell of `after` had no room (build only).
  // `before` must be the box f was last listed with.
  bool Move(uint32_t f, const Box& before, const Box* after);
  // One face's move, for CommitMoves: from `before` to `after`, or out of the index (removed).
  struct FaceMove {
    uint32_t face;
    bool removed;
    Box before, after;
  };
  // A commit's moves at once and its Track figures: in a round, recorded under one lock with
  // the figures summed per shard until the round ends (so that contexts do not share a cache
  // line per commit). False as Move.
  bool CommitMoves(std::span<const FaceMove> moves, double length_change, int64_t face_change);

  double cell_size() const { return cell_; }
  // The largest coordinate magnitude of the live faces' corners when last measured: positions
  // never change, and faces only ever join those vertices.
  double magnitude() const { return magnitude_; }

 private:
  static constexpr uint64_t kEmpty = 0;
  static constexpr int kMaxCellsPerBox = 1024;

  // A face listed in a cell, with its box in 1/256ths of a cell from the cell's lower corner,
  // rounded outwards and clamped (enough to pass over faces far from a collapse without reading
  // them); lo is negative on an axis iff the face's cells begin before this one.
  struct Listing {
    uint32_t face;
    int16_t lo[3], hi[3];
  };
  static constexpr int kListingBits = 8;

  // A cell's list is a slice of arena_ (made by Fill) until it outgrows it, then `grown`.
  struct Cell {
    std::atomic<uint64_t> key{kEmpty};  // packed cell coordinates + 1
    std::atomic<uint32_t> locked{0};
    uint32_t size = 0, capacity = 0;  // the list, guarded by `locked`
    Listing* data = nullptr;
    std::unique_ptr<Listing[]> grown;
    std::span<const Listing> list() const { return {data, size}; }
  };

  struct Range {
    int64_t lo[3], hi[3];
    int64_t count() const {
      return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    }
  };
  static constexpr uint32_t kPollFaces = 1 << 16;
  // What a move does to one cell: its listing dropped, rewritten (or added, when the cell
  // lacks it), or added.
  struct CellOp {
    uint64_t key;
    Listing listing;
    enum Kind : uint8_t { kDrop, kRelist, kAdd } kind;
  };
  // Calls emit(op) for every cell a move of face f changes.
  template <class Emit>
  void ForEachCellOp(uint32_t f, const Box& before, const Box* after, Emit&& emit) const;
  // False when an added listing found no room in the table. `lock`: the cell is locked for the
  // change (otherwise the caller holds it).
  bool Apply(const CellOp& op, bool lock = false);
  void Rebuild(const Mesh& mesh, const std::function<bool()>& cancelled);
  static void Append(Cell& cell, const Listing& listing);
  // A box in listing units from the origin (its corners' coordinates in cells, as RangeOf has
  // always computed them, times 2^kListingBits: exact; rounded down and up), and the cells it
  // covers (the floors of those coordinates).
  struct Span {
    int64_t lo[3], hi[3];
    Range range;
  };
  Span SpanOf(const Box& box) const;
  Range RangeOf(const Box& box) const { return SpanOf(box).range; }
  // Face f's listing in cell (x, y, z), for its box's span s.
  static Listing ListingIn(uint32_t f, const Span& s, int64_t x, int64_t y, int64_t z);
  // floor(t) and ceil(t) for t within [-2^62, 2^62] (std::floor is a library call here).
  static int64_t Floor(double t) {
    const int64_t i = static_cast<int64_t>(t);
    return i - (static_cast<double>(i) > t);
  }
  static int64_t Ceil(double t) {
    const int64_t i = static_cast<int64_t>(t);
    return i + (static_cast<double>(i) < t);
  }
  // A span's bound relative to cell c, clamped to a listing's range (integers: exact).
  static int16_t Relative(int64_t units, int64_t c) {
    return static_cast<int16_t>(std::clamp<int64_t>(units - (c << kListingBits), -32768, 32767));
  }
  // Indexes the live faces with cells of the current size in a table of at least min_capacity
  // (stops half done once `cancelled` says true).
  void Fill(const std::vector<uint32_t>& live, uint64_t min_capacity,
            const std::function<bool()>& cancelled);
  static std::vector<uint32_t> LiveFaces(const Mesh& mesh);
  // Runs body(chunk, begin, end) over [0, count) in chunks of kPollFaces, on the pool when
  // there is one, polling `cancelled` (may be empty) before each chunk; false once it said
  // true. Chunks, not contexts, split the work: what is summed per chunk adds up the same for
  // any number of contexts.
  template <class Body>
  bool ForEachChunk(size_t count, const std::function<bool()>& cancelled, Body&& body) const;
  // Mean edge length of the live faces (and the live faces, and their lower corner).
  // Records the sum and the faces as the tracked ones.
  double MeanEdge(const Mesh& mesh, std::vector<uint32_t>* live, DVec3* lo);
  template <class Visit>
  void ForEachCell(const Range& r, Visit&& visit) const {
    for (int64_t x = r.lo[0]; x <= r.hi[0]; ++x)
      for (int64_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (int64_t z = r.lo[2]; z <= r.hi[2]; ++z) visit(Key(x, y, z));
  }
  uint64_t Key(int64_t x, int64_t y, int64_t z) const;
  bool Overlaps(uint64_t key, const Box& box) const;
  // The slot of a cell, claimed if new; -1 when the table is full.
  int64_t Slot(uint64_t key);
  int64_t Find(uint64_t key) const;

  const VertexQ* vertices_;
  const HalfEdgeQ* halfedges_;
  const uint32_t* point_ids_;
  WorkerPool* pool_;
  DVec3 origin_{};
  double cell_ = 1.0;
  double magnitude_ = 0.0;
  uint64_t mask_ = 0;
  HugePageArray<Cell> cells_;
  HugePageArray<Listing> arena_;
  std::atomic<uint64_t> used_{0};
  // Deterministic rounds: the moves recorded while the lists are read only.
  bool deferred_ = false;
  // A round's commits record their moves in the shard of their thread (one lock each, on its
  // own cache line, so that contexts do not queue on one); ApplyMoves reads them in place, move
  // i in the shard whose range of shard_start_ holds it.
  static constexpr size_t kPendingShards = 16;
  struct alignas(64) PendingShard {
    std::mutex mu;
    std::vector<FaceMove> moves;  // guarded by mu
    double length_change = 0.0;   // the commits' Track figures, guarded by mu
    int64_t face_change = 0;
  };
  // Adds the shards' Track figures to the tracked ones, in shard order (one thread).
  void TrackShards();
  std::array<PendingShard, kPendingShards> shards_;
  std::array<size_t, kPendingShards + 1> shard_start_{};
  std::atomic<bool> unlisted_{false};        // a move of the round found no room
  std::atomic<double> tracked_length_{0.0};  // see Track
  std::atomic<int64_t> tracked_faces_{0};
};

}  // namespace femsimp
