#include "engine/rounds.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "engine/port.h"
#include "engine/ring.h"
#include "engine/star.h"

namespace femsimp {
namespace {

// The window starts at a 64th of the pass's removable vertices and adapts to how many of its
// candidates win: halved when fewer than half do (its candidates crowd each other), doubled
// when more than 80 % do. It follows the rounds' outcomes only, never the context count.
constexpr size_t kFirstWindowShare = 64;
constexpr size_t kLargestWindowShare = 32;  // and short rounds answer a cancel sooner
constexpr size_t kMinWindow = 256;
// Fans read ahead of the one being read (NativePort::PrefetchVertex, PrefetchFan).
constexpr size_t kPrefetchAhead = 4;
// ReadFansAndPick takes the window in chunks of at most this many candidates (a cancel is
// polled per chunk).
constexpr size_t kFanChunk = 256;
// The face index's moves are shared out in chunks of at most this many.
constexpr size_t kMoveChunk = 256;
// PickWinners' table of cells starts with this many slots (a power of two) and doubles as needed.
constexpr size_t kFirstPickCells = 4096;

// Boxes are widened by this much relative to their coordinates, so that two winners' new
// triangles are never closer than the intersection test's own near-touching margin.
constexpr double kBoxMargin = 1e-9;

bool Overlap(const FaceGrid::Box& a, const FaceGrid::Box& b) {
  return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
         a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}

// Cell coordinates of PickWinners' grid, mixed into one key (collisions only cost a box test).
uint64_t CellKey(int64_t x, int64_t y, int64_t z) {
  return static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ULL ^
         static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4FULL ^ static_cast<uint64_t>(z);
}

}  // namespace

RoundScheduler::RoundScheduler(Mesh& mesh, WorkerPool& pool, FaceGrid* grid, const RuleSet& rules,
                               bool placement, bool check_kept_boxes)
    : mesh_(mesh),
      pool_(pool),
      grid_(grid),
      rules_(rules),
      placement_(placement),
      check_kept_boxes_(check_kept_boxes),
      fan_shares_(pool.size()),
      move_shares_(pool.size()) {}

absl::StatusOr<uint64_t> RoundScheduler::ReadFansAndPick(const RemovalPhase& phase, int64_t room,
                                                         size_t* won) {
  *won = 0;
  const size_t m = window_.size();
  box_.resize(m);
  live_.assign(m, 0);
  by_vertex_.resize(m);  // (vertex, window entry), sorted as plain keys by context 0
  std::atomic<uint64_t> kept{0};
  std::atomic<uint32_t> differs{kNone};  // check_kept_boxes: a vertex whose kept box is wrong
  // A candidate's box: V and its one-ring (with full-edge collapses, the box of every star of
  // V, widened as the placed vertex may go: star.h's WidenForPlacement). Returns whether the
  // box was kept from an earlier round.
  const auto read = [&](NativePort& port, Ring& ring, Ring& outer, size_t i) {
    const uint32_t k = static_cast<uint32_t>(by_vertex_[i]);
    const uint32_t v = static_cast<uint32_t>(by_vertex_[i] >> 32);
    if (port.LoadStatus(v) != kRemovable) return false;
    live_[k] = 1;
    // A loser's box, from an earlier round of the pass, holds while no collapse since has
    // changed the one-ring of V (with placement, or of a neighbour; StampChanges): every ring it
    // was made of is as it was. Reading them all again was most of a placement round.
    const bool keep = box_round_[k] != 0 && Untouched(v, k, box_round_[k]);
    if (keep && !check_kept_boxes_) {
      box_[k] = cached_box_[k];
      return true;
    }
    nbr_count_[k] = 0;
    // A fan that cannot be read is V alone: the kernel refuses it without a neighbour.
    const VertexQ q = port.ReadVertex(v);
    const DVec3 at{q.x, q.y, q.z};
    FaceGrid::Box b{at, at};
    const auto grow = [](FaceGrid::Box& box, const Vec3& p) {
      box.lo = {std::min(box.lo.x, double(p.x)), std::min(box.lo.y, double(p.y)),
                std::min(box.lo.z, double(p.z))};
      box.hi = {std::max(box.hi.x, double(p.x)), std::max(box.hi.y, double(p.y)),
                std::max(box.hi.z, double(p.z))};
    };
    if (GatherRing(port, v, ring) == RingResult::kOk) {
      for (int r = 0; r < ring.neighbours(); ++r) grow(b, ring.pos[r]);
      // A full-edge collapse onto a neighbour reaches the neighbour's one-ring and places the
      // vertex within the widened box of the two (EdgeStar::lo, hi). A ring that cannot be
      // read is refused by the kernel.
      if (placement_) {
        nbr_count_[k] = static_cast<uint8_t>(ring.neighbours());
        std::copy_n(ring.nbr, ring.neighbours(), &nbrs_[size_t{k} * kMaxRing]);
        const FaceGrid::Box fan = b;
        for (int r = 0; r < ring.neighbours(); ++r) {
          if (GatherRing(port, ring.nbr[r], outer) != RingResult::kOk) continue;
          FaceGrid::Box star = fan;
          for (int j = 0; j < outer.neighbours(); ++j) grow(star, outer.pos[j]);
          WidenForPlacement(&star.lo, &star.hi);
          b.lo = {std::min(b.lo.x, star.lo.x), std::min(b.lo.y, star.lo.y),
                  std::min(b.lo.z, star.lo.z)};
          b.hi = {std::max(b.hi.x, star.hi.x), std::max(b.hi.y, star.hi.y),
                  std::max(b.hi.z, star.hi.z)};
        }
      }
    }
    const double scale =
        std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x),
                  std::fabs(b.hi.y), std::fabs(b.hi.z), Norm(b.hi - b.lo)});
    const DVec3 margin{kBoxMargin * scale, kBoxMargin * scale, kBoxMargin * scale};
    box_[k] = {b.lo - margin, b.hi + margin};
    if (keep) {
      const FaceGrid::Box& c = cached_box_[k];
      if (!(c.lo.x == box_[k].lo.x && c.lo.y == box_[k].lo.y && c.lo.z == box_[k].lo.z &&
            c.hi.x == box_[k].hi.x && c.hi.y == box_[k].hi.y && c.hi.z == box_[k].hi.z))
        differs.store(v, std::memory_order_relaxed);
      return true;
    }
    box_round_[k] = round_;
    return false;
  };
  // Context 0 sorts the window in vertex order (for locality: it is in cost order, scattered
  // over the mesh) while the others apply the last round's face index moves. Then context c
  // reads the c-th share of the window (the winners among them are its share of the removal
  // run too, so their fans are still in its cache), in chunks from the front, then what is left
  // of the others'. The context that reads the last fan picks the winners, while the others
  // apply the rest of the moves: neither the fan reads nor the pick look at the index, and the
  // sort and the pick are the round's serial steps.
  const size_t moves = index_updates_pending_ && !phase.Stopped() ? grid_->MovesOfRound() : 0;
  move_shares_.Reset(moves);
  fan_shares_.Reset(m);
  std::atomic<size_t> fans_read{0};
  std::atomic<bool> sorted{false};
  const int n = pool_.size();
  pool_.Run([&](int c) {
    NativePort port(mesh_);
    Ring ring, outer;
    size_t begin, end;
    if (c == 0) {
      for (uint32_t k = 0; k < m; ++k)
        by_vertex_[k] = uint64_t{phase.candidates[window_[k]]} << 32 | k;
      std::sort(by_vertex_.begin(), by_vertex_.end());
      sorted.store(true, std::memory_order_release);
    } else {
      while (!sorted.load(std::memory_order_acquire) &&
             move_shares_.Next(c, kMoveChunk, &begin, &end))
        grid_->ApplyMoves(begin, end, /*shared=*/true);
      while (!sorted.load(std::memory_order_acquire)) SpinPause();
    }
    const auto read_fans = [&](size_t begin, size_t end) {
      uint64_t kept_here = 0;
      for (size_t i = begin; i < end; ++i) {
        if (i + 2 * kPrefetchAhead < m)
          port.PrefetchVertex(static_cast<uint32_t>(by_vertex_[i + 2 * kPrefetchAhead] >> 32));
        if (i + kPrefetchAhead < m)
          port.PrefetchFan(static_cast<uint32_t>(by_vertex_[i + kPrefetchAhead] >> 32));
        kept_here += read(port, ring, outer, i);
      }
      kept.fetch_add(kept_here, std::memory_order_relaxed);
    };
    while (fan_shares_.Next(c, kFanChunk, &begin, &end)) {
      if (phase.Stopped() || phase.PollCancelled()) return;
      read_fans(begin, end);
      // Release: the boxes read here; acquire: the others' (the pick reads them all).
      if (fans_read.fetch_add(end - begin, std::memory_order_acq_rel) + (end - begin) == m)
        *won = PickWinners(phase, room);
    }
    while (move_shares_.Next(c, kMoveChunk, &begin, &end)) {
      if (phase.Stopped() || phase.PollCancelled()) return;
      grid_->ApplyMoves(begin, end, /*shared=*/n > 1);
    }
  });
  FinishIndexUpdates(phase, /*applied=*/true);
  if (const uint32_t v = differs.load(); v != kNone)
    return absl::InternalError(absl::StrCat("round ", round_, ": the box of vertex ", v,
                                            " kept from an earlier round is not what it reads"));
  return kept.load();
}

void RoundScheduler::FinishIndexUpdates(const RemovalPhase& phase, bool applied) {
  if (!index_updates_pending_) return;
  index_updates_pending_ = false;
  // A cancelled run stops in the middle of a round, and the face index is not used again.
  if (phase.Stopped())
    grid_->AbandonRound();
  else if (applied)
    grid_->FinishRound(mesh_);
  else
    grid_->EndRound(mesh_);
}

void RoundScheduler::StampChanges() {
  if (touched_.size() < mesh_.vertex_capacity()) touched_.resize(mesh_.vertex_capacity(), 0);
  for (uint32_t u : changed_) touched_[u] = round_;
  changed_.clear();
}

bool RoundScheduler::Untouched(uint32_t v, uint32_t k, uint32_t since) const {
  if (touched_[v] >= since) return false;
  if (nbr_count_[k] == 0) return true;  // no placement: V's one-ring alone made its box
  const uint32_t* nbr = &nbrs_[size_t{k} * kMaxRing];
  for (int r = 0; r < nbr_count_[k]; ++r)
    if (touched_[nbr[r]] >= since) return false;
  return true;
}

size_t RoundScheduler::PickWinners(const RemovalPhase& phase, int64_t room) {
  const size_t m = window_.size();
  // Winners' boxes are listed in a hashed grid whose cells are about twice the typical box, so
  // a box meets a few cells and each cell few winners; a box over more cells than kMaxCells is
  // checked against every winner instead (rare: a fan much larger than the rest).
  constexpr int64_t kMaxCells = 64;
  extent_.clear();
  DVec3 origin{1e300, 1e300, 1e300};
  for (size_t k = 0; k < m; ++k) {
    if (!live_[k]) continue;
    const DVec3 d = box_[k].hi - box_[k].lo;
    extent_.push_back(std::max({d.x, d.y, d.z}));
    origin = {std::min(origin.x, box_[k].lo.x), std::min(origin.y, box_[k].lo.y),
              std::min(origin.z, box_[k].lo.z)};
  }
  won_.assign(m, 0);
  if (extent_.empty()) return 0;
  std::nth_element(extent_.begin(), extent_.begin() + extent_.size() / 2, extent_.end());
  // Any cell size finds every overlap (boxes that overlap or touch share a cell, the cell of a
  // coordinate being monotone in it), so the product with the reciprocal serves as well as
  // the quotient.
  const double per_cell = 1.0 / std::max(2.0 * extent_[extent_.size() / 2], 1e-300);
  const auto range = [&](const FaceGrid::Box& b, int64_t lo[3], int64_t hi[3]) {
    const double l[3] = {b.lo.x - origin.x, b.lo.y - origin.y, b.lo.z - origin.z};
    const double h[3] = {b.hi.x - origin.x, b.hi.y - origin.y, b.hi.z - origin.z};
    int64_t count = 1;
    for (int a = 0; a < 3; ++a) {
      // Both are at least 0 (the origin is the least corner), where truncation floors.
      lo[a] = static_cast<int64_t>(std::min(l[a] * per_cell, 1e15));
      hi[a] = static_cast<int64_t>(std::min(h[a] * per_cell, 1e15));
      count *= hi[a] - lo[a] + 1;
      if (count > kMaxCells) return false;
    }
    return true;
  };
  // The table keeps its slots from round to round (clearing a hash map of this size frees it):
  // a slot is taken in this pick when it carries this pick's stamp.
  if (++pick_stamp_ == 0) {
    for (PickCell& cell : pick_cells_) cell.stamp = 0;
    pick_stamp_ = 1;
  }
  if (pick_cells_.empty()) pick_cells_.resize(kFirstPickCells);
  size_t taken = 0;
  const auto slot_of = [&](uint64_t key) {
    const size_t mask = pick_cells_.size() - 1;
    size_t i = static_cast<size_t>((key * 0x9E3779B97F4A7C15ULL) >> 32) & mask;
    while (pick_cells_[i].stamp == pick_stamp_ && pick_cells_[i].key != key) i = (i + 1) & mask;
    return i;
  };
  const auto take = [&](uint64_t key) -> PickCell& {
    size_t i = slot_of(key);
    if (pick_cells_[i].stamp == pick_stamp_) return pick_cells_[i];
    if (2 * (taken + 1) > pick_cells_.size()) {  // at most half full: probes stay short
      std::vector<PickCell> old(2 * pick_cells_.size());
      old.swap(pick_cells_);
      for (const PickCell& cell : old)
        if (cell.stamp == pick_stamp_) pick_cells_[slot_of(cell.key)] = cell;
      i = slot_of(key);
    }
    ++taken;
    pick_cells_[i] = {key, pick_stamp_, kNone};
    return pick_cells_[i];
  };
  listed_.clear();  // (winner, next listing in the same cell)
  big_.clear();
  size_t winners = 0;
  int64_t lo[3] = {}, hi[3] = {};
  for (uint32_t k = 0; k < m && static_cast<int64_t>(winners) < room; ++k) {
    if (k % 1024 == 0 && phase.PollCancelled()) return winners;
    if (!live_[k]) continue;
    const FaceGrid::Box& box = box_[k];
    const bool small = range(box, lo, hi);
    bool blocked = false;
    for (uint32_t w : big_) blocked = blocked || Overlap(box, box_[w]);
    if (!small) {
      for (size_t i = 0; i < winners && !blocked; ++i) blocked = Overlap(box, box_[order_[i]]);
    } else {
      for (int64_t x = lo[0]; x <= hi[0] && !blocked; ++x)
        for (int64_t y = lo[1]; y <= hi[1] && !blocked; ++y)
          for (int64_t z = lo[2]; z <= hi[2] && !blocked; ++z) {
            const PickCell& cell = pick_cells_[slot_of(CellKey(x, y, z))];
            if (cell.stamp != pick_stamp_) continue;
            for (uint32_t e = cell.head; e != kNone && !blocked; e = listed_[e].second)
              blocked = Overlap(box, box_[listed_[e].first]);
          }
    }
    if (blocked) continue;
    won_[k] = 1;
    if (order_.size() <= winners) order_.resize(winners + 1);
    order_[winners++] = k;
    if (!small) {
      big_.push_back(k);
      continue;
    }
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          PickCell& cell = take(CellKey(x, y, z));
          listed_.emplace_back(k, cell.head);
          cell.head = static_cast<uint32_t>(listed_.size() - 1);
        }
  }
  return winners;
}

absl::Status RoundScheduler::RunPass(RemovalBackend& backend, const RemovalPhase& phase,
                                     PassStats& stats) {
  const size_t largest = std::max(kMinWindow, phase.sorted / kLargestWindowShare);
  size_t window_size = std::max(kMinWindow, phase.sorted / kFirstWindowShare);
  std::vector<uint32_t> losers, winners, ranks;
  // Each loser's box and the round it was read in; with placement, V's neighbours then.
  std::vector<FaceGrid::Box> loser_boxes;
  std::vector<uint32_t> loser_rounds, loser_nbrs;
  std::vector<uint8_t> loser_nbr_counts;
  std::vector<FaceGrid::Box> winner_boxes;  // hints for the face index (RemovalPhase::boxes)
  size_t fresh = 0;
  for (bool first = true; !phase.Stopped(); first = false) {
    // Losers first: they rank before every fresh candidate, so the window stays in cost order.
    window_.swap(losers);
    losers.clear();
    cached_box_.swap(loser_boxes);
    loser_boxes.clear();
    box_round_.swap(loser_rounds);
    loser_rounds.clear();
    nbrs_.swap(loser_nbrs);
    loser_nbrs.clear();
    nbr_count_.swap(loser_nbr_counts);
    loser_nbr_counts.clear();
    while (window_.size() < window_size && fresh < phase.count)
      window_.push_back(static_cast<uint32_t>(fresh++));
    cached_box_.resize(window_.size());
    box_round_.resize(window_.size(), 0);
    nbr_count_.resize(window_.size(), 0);
    if (placement_) nbrs_.resize(window_.size() * kMaxRing);
    if (window_.empty() || phase.PollCancelled()) break;
    const RemovalBudget& budget = *phase.budget;
    const int64_t room = budget.target > 0 ? budget.alive.load() - budget.target : INT64_MAX;
    if (room <= 0) break;
    const auto start = std::chrono::steady_clock::now();
    ++round_;
    size_t won = 0;
    absl::StatusOr<uint64_t> kept = ReadFansAndPick(phase, room, &won);
    if (!kept.ok()) return kept.status();
    stats.boxes_kept += *kept;
    if (phase.Stopped()) break;
    const size_t live = static_cast<size_t>(std::count(live_.begin(), live_.end(), 1));
    if (2 * won < live)
      window_size = std::max(kMinWindow, window_size / 2);
    else if (5 * won > 4 * live)
      window_size = std::min(largest, 2 * window_size);
    for (size_t k = 0; k < window_.size(); ++k)
      if (live_[k] && !won_[k]) {
        losers.push_back(window_[k]);
        loser_boxes.push_back(box_[k]);
        loser_rounds.push_back(box_round_[k]);
        loser_nbr_counts.push_back(nbr_count_[k]);
        if (placement_) {
          loser_nbrs.insert(loser_nbrs.end(), nbrs_.begin() + k * kMaxRing,
                            nbrs_.begin() + k * kMaxRing + nbr_count_[k]);
          loser_nbrs.resize(loser_nbr_counts.size() * kMaxRing);
        }
      }
    // Their outcomes do not depend on the order they run in: by vertex number (as ReadFansAndPick
    // read them), for locality.
    winners.clear();
    ranks.clear();
    winner_boxes.clear();
    for (uint64_t entry : by_vertex_)
      if (won_[static_cast<uint32_t>(entry)]) {
        winners.push_back(static_cast<uint32_t>(entry >> 32));
        ranks.push_back(static_cast<uint32_t>(entry));
        if (grid_ != nullptr) winner_boxes.push_back(box_[static_cast<uint32_t>(entry)]);
      }
    stats.busy_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    RemovalPhase round = phase;
    round.candidates = winners.data();
    round.count = winners.size();
    round.pass_start = first;
    round.claimed = window_.size();
    round.window_rank = ranks.data();
    round.fresh_caches = true;
    round.blocks = true;
    round.changed = &changed_;
    if (grid_ != nullptr) {
      round.boxes = winner_boxes.data();
      round.grid = grid_;
    }
    rules_.BeginRound(winners.size());
    if (grid_ != nullptr) {
      uint64_t new_cells = 0;  // at most: the kernel's fan boxes lie within the winners'
      for (size_t i = 0; i < won; ++i) new_cells += grid_->CellsOf(box_[order_[i]]);
      grid_->BeginRound(mesh_, new_cells);
    }
    absl::Status s = backend.RunRemoval(round, stats);
    if (s.ok()) StampChanges();
    index_updates_pending_ = grid_ != nullptr;
    rules_.EndRound();
    if (!s.ok()) {
      FinishIndexUpdates(phase, /*applied=*/false);
      return s;
    }
    ++stats.rounds;
  }
  FinishIndexUpdates(phase, /*applied=*/false);
  return absl::OkStatus();
}

}  // namespace femsimp
