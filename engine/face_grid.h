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

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "engine/mesh.h"
#include "engine/triangle_intersection.h"
#include "engine/vec.h"

namespace femsimp {

class FaceGrid {
 public:
  // Indexes the live faces of `mesh`, which must outlive the grid.
  explicit FaceGrid(const Mesh& mesh);
  // Between passes (nothing held): indexes the mesh anew when its faces have grown well past
  // the cells (as the mesh coarsens), so that a fan still covers a few cells.
  void Refresh(const Mesh& mesh);

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
  // so they need no cell locks, and the index stays as it was at the round's start while they
  // run: Acquire only finds the cells (it never locks or creates one), Release forgets them,
  // and Move is recorded. EndRound applies the moves in face order (a face moves at most once
  // a round) and indexes the mesh anew in a larger table if a new cell found no room.
  void BeginRound() { deferred_ = true; }
  void EndRound(const Mesh& mesh);

  // Calls visit(face) for every face listed in the held cells that overlap `box` (a face may
  // come more than once); stops early when visit returns false.
  template <class Visit>
  void ForEachFace(const Box& box, const std::vector<uint32_t>& held, Visit&& visit) const {
    for (uint32_t slot : held) {
      if (!Overlaps(cells_[slot].key.load(std::memory_order_relaxed), box)) continue;
      for (uint32_t f : cells_[slot].faces)
        if (!visit(f)) return;
    }
  }

  // The corners of face f as they are in the mesh now (f must be in a held cell).
  Triangle FaceTriangle(uint32_t f) const;

  // Moves face f in the index from the cells of `before` to those of `after` (both within held
  // cells); an empty `after` removes it. False when a cell of `after` had no room (build only).
  bool Move(uint32_t f, const Box& before, const Box* after);

  double cell_size() const { return cell_; }

 private:
  static constexpr uint64_t kEmpty = 0;
  static constexpr int kMaxCellsPerBox = 1024;

  struct Cell {
    std::atomic<uint64_t> key{kEmpty};  // packed cell coordinates + 1
    std::atomic<uint32_t> locked{0};
    std::vector<uint32_t> faces;  // guarded by `locked`
  };

  struct Range {
    int64_t lo[3], hi[3];
    int64_t count() const {
      return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    }
  };
  void Rebuild(const Mesh& mesh);
  // Indexes the live faces with cells of the current size in a table of at least min_capacity.
  void Fill(const std::vector<uint32_t>& live, uint64_t min_capacity);
  // Mean edge length of the live faces (and the live faces, and their lower corner).
  double MeanEdge(const Mesh& mesh, std::vector<uint32_t>* live, DVec3* lo) const;
  Range RangeOf(const Box& box) const;
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
  DVec3 origin_{};
  double cell_ = 1.0;
  uint64_t mask_ = 0;
  std::unique_ptr<Cell[]> cells_;
  std::atomic<uint64_t> used_{0};
  // Deterministic rounds: the moves recorded while the index is read only.
  struct PendingMove {
    uint32_t face;
    bool removed;
    Box before, after;
  };
  bool deferred_ = false;
  std::mutex pending_mu_;
  std::vector<PendingMove> pending_;  // guarded by pending_mu_
};

}  // namespace femsimp
