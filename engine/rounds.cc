#include "engine/rounds.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/port.h"
#include "engine/ring.h"

namespace femsimp {
namespace {

// The window starts at a 64th of the pass's removable vertices and adapts to how many of its
// candidates win: halved when fewer than half do (its candidates crowd each other), doubled
// when more than 80 % do. It follows the rounds' outcomes only, never the context count.
constexpr size_t kFirstWindowShare = 64;
constexpr size_t kLargestWindowShare = 8;
constexpr size_t kMinWindow = 256;

// Boxes are widened by this much relative to their coordinates, so that two winners' new
// triangles are never closer than the intersection test's own near-touching margin.
constexpr double kBoxMargin = 1e-9;

bool Overlap(const FaceGrid::Box& a, const FaceGrid::Box& b) {
  return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
         a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}

double Axis(const DVec3& p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

}  // namespace

RoundScheduler::RoundScheduler(Mesh& mesh, WorkerPool& pool, FaceGrid* grid, const RuleSet& rules)
    : mesh_(mesh), pool_(pool), grid_(grid), rules_(rules) {}

void RoundScheduler::ReadFans(const RemovalPhase& phase) {
  const size_t m = window_.size();
  box_.resize(m);
  live_.assign(m, 0);
  // Read in vertex order, for locality (the window is in cost order, scattered over the mesh).
  by_vertex_.resize(m);
  for (uint32_t k = 0; k < m; ++k) by_vertex_[k] = k;
  std::sort(by_vertex_.begin(), by_vertex_.end(), [&](uint32_t a, uint32_t b) {
    return phase.candidates[window_[a]] < phase.candidates[window_[b]];
  });
  const int n = pool_.size();
  pool_.Run([&](int c) {
    NativePort port(mesh_);
    Ring ring;
    DVec3 points[kMaxRing + 2];
    for (size_t i = m * c / n; i < m * (c + 1) / n; ++i) {
      if (i % kCancelPollInterval == 0 && (phase.Stopped() || phase.PollCancelled())) return;
      const uint32_t k = by_vertex_[i];
      const uint32_t v = phase.candidates[window_[k]];
      if (port.LoadStatus(v) != kRemovable) continue;
      live_[k] = 1;
      // A fan that cannot be read is V alone: the kernel refuses it without a neighbour.
      const VertexQ q = port.ReadVertex(v);
      points[0] = {q.x, q.y, q.z};
      int count = 1;
      if (GatherRing(port, v, ring) == RingResult::kOk)
        for (int i = 0; i < ring.neighbours(); ++i) points[count++] = ToD(ring.pos[i]);
      FaceGrid::Box b = FaceGrid::BoxOf(points, count);
      const double scale =
          std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x),
                    std::fabs(b.hi.y), std::fabs(b.hi.z), Norm(b.hi - b.lo)});
      const DVec3 margin{kBoxMargin * scale, kBoxMargin * scale, kBoxMargin * scale};
      box_[k] = {b.lo - margin, b.hi + margin};
    }
  });
}

size_t RoundScheduler::PickWinners(int64_t room) {
  const size_t m = window_.size();
  // Overlapping pairs by a sweep along the axis the boxes spread most along (fewest pairs
  // overlap there only).
  by_x_.clear();
  DVec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (uint32_t k = 0; k < m; ++k) {
    if (!live_[k]) continue;
    by_x_.push_back(k);
    lo = {std::min(lo.x, box_[k].lo.x), std::min(lo.y, box_[k].lo.y), std::min(lo.z, box_[k].lo.z)};
    hi = {std::max(hi.x, box_[k].lo.x), std::max(hi.y, box_[k].lo.y), std::max(hi.z, box_[k].lo.z)};
  }
  const DVec3 spread = hi - lo;
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
  std::sort(by_x_.begin(), by_x_.end(), [&](uint32_t a, uint32_t b) {
    const double la = Axis(box_[a].lo, axis), lb = Axis(box_[b].lo, axis);
    return la < lb || (la == lb && a < b);
  });
  overlaps_.clear();
  for (size_t a = 0; a < by_x_.size(); ++a) {
    const FaceGrid::Box& box = box_[by_x_[a]];
    const double end = Axis(box.hi, axis);
    for (size_t b = a + 1; b < by_x_.size() && Axis(box_[by_x_[b]].lo, axis) <= end; ++b)
      if (Overlap(box, box_[by_x_[b]]))
        overlaps_.emplace_back(std::min(by_x_[a], by_x_[b]), std::max(by_x_[a], by_x_[b]));
  }
  std::sort(overlaps_.begin(), overlaps_.end());
  // Greedy in cost order: a winner blocks every later candidate its box overlaps.
  won_.assign(m, 0);
  open_ = live_;  // 1: no better-ranked winner overlaps it
  size_t winners = 0;
  for (size_t k = 0, e = 0; k < m; ++k) {
    if (open_[k] && static_cast<int64_t>(winners) < room) {
      won_[k] = 1;
      ++winners;
    }
    for (; e < overlaps_.size() && overlaps_[e].first == k; ++e)
      if (won_[k]) open_[overlaps_[e].second] = 0;
  }
  return winners;
}

absl::Status RoundScheduler::RunPass(RemovalBackend& backend, const RemovalPhase& phase,
                                     PassStats& stats) {
  const size_t largest = std::max(kMinWindow, phase.sorted / kLargestWindowShare);
  size_t window_size = std::max(kMinWindow, phase.sorted / kFirstWindowShare);
  std::vector<uint32_t> losers, winners;
  size_t fresh = 0;
  for (bool first = true; !phase.Stopped(); first = false) {
    // Losers first: they rank before every fresh candidate, so the window stays in cost order.
    window_.swap(losers);
    losers.clear();
    while (window_.size() < window_size && fresh < phase.count)
      window_.push_back(static_cast<uint32_t>(fresh++));
    if (window_.empty() || phase.PollCancelled()) break;
    const RemovalBudget& budget = *phase.budget;
    const int64_t room = budget.target > 0 ? budget.alive.load() - budget.target : INT64_MAX;
    if (room <= 0) break;
    const auto start = std::chrono::steady_clock::now();
    ReadFans(phase);
    if (phase.Stopped()) break;
    const size_t live = static_cast<size_t>(std::count(live_.begin(), live_.end(), 1));
    const size_t won = PickWinners(room);
    if (2 * won < live)
      window_size = std::max(kMinWindow, window_size / 2);
    else if (5 * won > 4 * live)
      window_size = std::min(largest, 2 * window_size);
    winners.clear();
    for (size_t k = 0; k < window_.size(); ++k) {
      if (won_[k])
        winners.push_back(phase.candidates[window_[k]]);
      else if (live_[k])
        losers.push_back(window_[k]);
    }
    // Their outcomes do not depend on the order they run in: by vertex number, for locality.
    std::sort(winners.begin(), winners.end());
    stats.busy_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    RemovalPhase round = phase;
    round.candidates = winners.data();
    round.count = winners.size();
    round.pass_start = first;
    round.claimed = window_.size();
    round.fresh_caches = true;
    round.blocks = true;
    rules_.BeginRound(winners.size());
    if (grid_ != nullptr) grid_->BeginRound();
    absl::Status s = backend.RunRemoval(round, stats);
    if (grid_ != nullptr) grid_->EndRound(mesh_);
    rules_.EndRound();
    if (!s.ok()) return s;
    ++stats.rounds;
  }
  return absl::OkStatus();
}

}  // namespace femsimp
