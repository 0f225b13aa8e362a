// Deterministic rounds (option schedule = deterministic): the candidates of a pass run in rounds
// of collapses that cannot interact, so the output depends on the input and the options only —
// not on timing, and not on the number of threads or SPEs.
//
// A round takes a window of the pass's candidates in cost order (the losers of the last round
// first, then fresh ones) and
//   1. reads, in parallel, each candidate's fan and its bounding box (V and its one-ring; with
//      full-edge collapses, the union of its stars' boxes, each widened as the placed vertex
//      may go: star.h's WidenForPlacement): everything its collapse can lock, write or create
//      lies in that box. A loser's box is kept from the round that read it while no collapse
//      since has changed the one-ring of V (or, with full-edge collapses, of a neighbour): each
//      round stamps the vertices its commits locked, which are those whose rings changed. Most
//      of a round's candidates can be losers of the round before (a placement round's boxes
//      are seven rings each; the large fans of a coarse CAD export overlap), and most winners
//      are refused and change nothing;
//   2. picks the winners greedily in cost order: a candidate wins unless its box overlaps the
//      box of a better-ranked winner (touching counts; found through a hashed grid of the
//      winners' boxes; with a vertex target, only as many winners as removals remain). The
//      others come back next round;
//   3. the winners run the kernel on the back end. Disjoint boxes mean disjoint locked sets, so
//      no lock conflict occurs, and what one reads is never written by another (kernel.h: a
//      collapse writes only quadwords of faces with two vertices in its locked set), so each
//      outcome is the one it would have against the mesh at the start of the round. Their new
//      triangles lie in disjoint boxes, so they cannot meet each other; the face index is read
//      only, its updates applied after the round (FaceGrid::BeginRound), by the contexts done
//      with the next round's fans while one of them picks its winners (neither looks at it). The
//      budget rules judge each winner against the round's starting totals with its change
//      scaled by the number of winners (MechanicsLedger::BeginRound): the round's total change
//      is then the mean of points within the budget, which is within it (the budgets are
//      convex), and the totals are summed in vertex order after the round.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "engine/face_grid.h"
#include "engine/mesh.h"
#include "engine/removal_backend.h"
#include "engine/rule.h"
#include "engine/work_shares.h"
#include "engine/worker_pool.h"

namespace femsimp {

class RoundScheduler {
 public:
  // grid: the self-intersection rule's index, or nullptr when that rule is off. placement:
  // full-edge collapses may run, which lock, move and rewrite within V's two-ring.
  // check_kept_boxes: every box kept from an earlier round is read again and compared (a
  // self-check for tests: RunPass fails on a difference).
  RoundScheduler(Mesh& mesh, WorkerPool& pool, FaceGrid* grid, const RuleSet& rules,
                 bool placement = false, bool check_kept_boxes = false);

  // Runs the pass's candidates (phase.candidates[0, phase.count)) to the end in rounds.
  absl::Status RunPass(RemovalBackend& backend, const RemovalPhase& phase, PassStats& stats);

 private:
  // Boxes of the window's candidates (in parallel); `live[k]` false: no longer removable. Then
  // PickWinners on the context that read the last box (*won: its result), while the others apply
  // the last round's face index moves, when pending. Returns how many boxes were kept from an
  // earlier round; with check_kept_boxes, an error for one that a fresh read does not give.
  absl::StatusOr<uint64_t> ReadFansAndPick(const RemovalPhase& phase, int64_t room, size_t* won);
  // Ends the last round's face index updates, if pending; `applied`: ReadFansAndPick applied its
  // moves (otherwise they are applied now, serially).
  void FinishIndexUpdates(const RemovalPhase& phase, bool applied);
  // Marks the winners in window order; returns how many.
  size_t PickWinners(const RemovalPhase& phase, int64_t room);
  // Stamps with this round every vertex the round's commits locked (KernelStats::changed).
  void StampChanges();
  // No vertex of {v} and, with placement, its one-ring is stamped at or after round `since`
  // (k: v's window entry, which keeps v's neighbours as its box was read), so that the rings
  // v's box was made of then are unchanged.
  bool Untouched(uint32_t v, uint32_t k, uint32_t since) const;

  Mesh& mesh_;
  WorkerPool& pool_;
  FaceGrid* grid_;
  const RuleSet& rules_;
  const bool placement_;
  const bool check_kept_boxes_;
  // Per window entry (reused between rounds).
  std::vector<uint32_t> window_;
  std::vector<FaceGrid::Box> box_;
  std::vector<uint8_t> live_, won_;
  // Each entry's box as an earlier round read it (losers carry theirs), the round it was read
  // in (0: none), the rounds so far in the run, and per vertex the last round whose commits
  // locked it.
  std::vector<FaceGrid::Box> cached_box_;
  std::vector<uint32_t> box_round_;
  std::vector<uint32_t> nbrs_;  // kMaxRing slots per entry: V's neighbours
  std::vector<uint8_t> nbr_count_;
  uint32_t round_ = 0;
  std::vector<uint32_t> touched_;
  std::vector<uint32_t> changed_;  // the round's KernelStats::changed
  std::vector<uint64_t> by_vertex_;
  bool index_updates_pending_ = false;
  // ReadFansAndPick: each context's share of the window (in vertex order) and of the last
  // round's face index moves, and what is left of them.
  WorkShares fan_shares_, move_shares_;
  // PickWinners: box extents, the winners so far, and a hashed grid of their boxes (a table of
  // cells kept from pick to pick, and the listings).
  std::vector<double> extent_;
  std::vector<uint32_t> order_, big_;
  struct PickCell {
    uint64_t key = 0;
    uint32_t stamp = 0;  // taken in the pick that has this stamp
    uint32_t head = 0;   // the cell's last listing
  };
  std::vector<PickCell> pick_cells_;  // open addressing, a power of two of slots
  uint32_t pick_stamp_ = 0;
  std::vector<std::pair<uint32_t, uint32_t>> listed_;  // (winner, previous listing in the cell)
};

}  // namespace femsimp
