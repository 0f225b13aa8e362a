#include "engine/seam_collapse.h"

#include <algorithm>
#include <utility>

#include "engine/triangle_intersection.h"

namespace femsimp {

SeamCollapser::SeamCollapser(Mesh& mesh, const PointCopies& copies, const RuleSet& rules,
                             bool quadric, FaceGrid* grid, bool requeue_changed)
    : mesh_(mesh),
      rules_(rules),
      quadric_(quadric),
      requeue_changed_(requeue_changed),
      grid_(grid),
      copies_(copies),
      port_(mesh) {}

SeamCollapser::~SeamCollapser() = default;

std::vector<uint32_t> SeamCollapser::VerticesOf(uint32_t p, uint32_t fallback) const {
  const std::span<const uint32_t> of = copies_.Of(p);
  if (of.empty()) return {fallback};
  return {of.begin(), of.end()};
}

SeamCollapser::SweepResult SeamCollapser::Sweep(RemovalBudget& budget) {
  SweepResult result;
  for (size_t k = 0; k < copies_.size(); ++k) {
    const size_t copies = copies_.copies(k).size();
    const uint32_t* copy = copies_.copies(k).data();
    if (mesh_.IsRemoved(copy[0])) continue;
    // Every copy a boundary vertex whose fan runs from one seam neighbour to the other, the
    // same two points in every sheet.
    if (rings_.size() < copies) rings_.resize(copies);
    uint32_t ends[2] = {kNone, kNone};
    bool inner = true;
    for (size_t c = 0; c < copies && inner; ++c) {
      Ring& ring = rings_[c];
      inner = GatherRing(port_, copy[c], ring) == RingResult::kOk && ring.boundary;
      if (!inner) break;
      uint32_t e[2] = {PointOf(ring.nbr[0]), PointOf(ring.nbr[ring.faces])};
      if (e[0] > e[1]) std::swap(e[0], e[1]);
      if (c == 0) {
        ends[0] = e[0];
        ends[1] = e[1];
      }
      inner = e[0] != e[1] && e[0] == ends[0] && e[1] == ends[1];
    }
    if (!inner) continue;
    // The shorter seam edge goes first.
    const Ring& r0 = rings_[0];
    const auto length2 = [&](uint32_t point) {
      const Vec3& p = PointOf(r0.nbr[0]) == point ? r0.pos[0] : r0.pos[r0.faces];
      const double dx = p.x - r0.center_pos.x, dy = p.y - r0.center_pos.y,
                   dz = p.z - r0.center_pos.z;
      return dx * dx + dy * dy + dz * dz;
    };
    const int first = length2(ends[1]) < length2(ends[0]) ? 1 : 0;
    for (const int d : {first, 1 - first}) {
      const Tried t = TryCompound(k, ends[d], ends[1 - d], budget);
      if (t == Tried::kRefused) continue;
      if (t == Tried::kBudgetSpent) {
        result.budget_spent = true;
        break;
      }
      ++result.points;
      result.vertices += copies;
      break;
    }
    if (result.budget_spent) break;
  }
  result.requeued.swap(scratch_stats_.requeued);
  return result;
}

SeamCollapser::Tried SeamCollapser::TryCompound(size_t point, uint32_t onto, uint32_t left,
                                                RemovalBudget& budget) {
  const size_t copies = copies_.copies(point).size();
  const uint32_t* copy = copies_.copies(point).data();
  // The copies' rings (gathered by Sweep, and nothing changed since): their targets, the faces
  // they rewrite, and the cells they may claim.
  targets_.assign(copies, kNone);
  replaced_.clear();
  uint64_t new_cells = 0;
  for (size_t c = 0; c < copies; ++c) {
    const Ring& ring = rings_[c];
    const int last = ring.faces;
    targets_[c] = PointOf(ring.nbr[0]) == onto ? ring.nbr[0] : ring.nbr[last];
    for (int f = 0; f < ring.faces; ++f) replaced_.push_back(FaceOf(ring.out[f]));
    if (grid_ != nullptr) {
      DVec3 points[kMaxRing + 2];
      points[0] = ToD(ring.center_pos);
      for (int i = 0; i < ring.neighbours(); ++i) points[i + 1] = ToD(ring.pos[i]);
      new_cells += grid_->CellsOf(FaceGrid::BoxOf(points, ring.neighbours() + 1));
    }
  }
  // The merged seam edge L-D must be new: no face of any sheet joins L and D already.
  const uint32_t left_vertex =
      PointOf(rings_[0].nbr[0]) == left ? rings_[0].nbr[0] : rings_[0].nbr[rings_[0].faces];
  if (AnyFaceJoins(left, left_vertex, onto)) return Tried::kRefused;

  while (kernels_.size() < copies) {
    ports_.push_back(std::make_unique<NativePort>(mesh_));
    kernels_.push_back(std::make_unique<RemovalKernel<NativePort>>(
        *ports_.back(), rules_, quadric_, no_budget_, scratch_stats_, false, requeue_changed_));
  }
  // The index is read only while the copies are checked: they overlap each other's cells by
  // design (the copies share their points), and their moves are applied together after.
  if (grid_ != nullptr) grid_->BeginRound(mesh_, new_cells);
  size_t held = 0;
  bool passed = true;
  for (; held < copies; ++held) {
    Reject refused = Reject::kCount;
    if (kernels_[held]->HoldCollapse(copy[held], targets_[held], replaced_, &refused) !=
        Verdict::kPass) {
      passed = false;
      break;
    }
  }
  Tried outcome = Tried::kRefused;
  if (passed && grid_ != nullptr && NewTrianglesMeet(copies)) passed = false;
  size_t reserved = 0;
  if (passed) {  // the vertex target first: a refused compound must not have spent budgets
    while (reserved < copies && budget.Reserve()) ++reserved;
    if (reserved < copies) {
      outcome = Tried::kBudgetSpent;
      passed = false;
    }
  }
  if (passed) {
    deltas_.assign(copies, CollapseDelta{});
    for (size_t c = 0; c < copies; ++c) deltas_[c] = kernels_[c]->held().delta;
    Reject refused = Reject::kCount;
    passed = rules_.SpendBudgetsTogether(deltas_, &refused);
  }
  if (!passed)
    while (reserved-- > 0) budget.Unreserve();
  if (passed) {
    for (size_t c = 0; c < copies; ++c) {
      kernels_[c]->CommitHeld();
      budget.Removed();
    }
    outcome = Tried::kRemoved;
  } else {
    for (size_t c = 0; c < held; ++c) kernels_[c]->ReleaseHeld();
  }
  if (grid_ != nullptr) grid_->EndRound(mesh_);
  return outcome;
}

bool SeamCollapser::AnyFaceJoins(uint32_t a_point, uint32_t a_vertex, uint32_t b_point) {
  Ring ring;
  for (uint32_t u : VerticesOf(a_point, a_vertex)) {
    if (mesh_.IsRemoved(u)) continue;
    if (GatherRing(port_, u, ring) != RingResult::kOk) return true;  // cannot tell: refuse
    for (int i = 0; i < ring.neighbours(); ++i)
      if (PointOf(ring.nbr[i]) == b_point) return true;
  }
  return false;
}

bool SeamCollapser::NewTrianglesMeet(size_t copies) const {
  std::vector<PreparedTriangle> fresh;
  std::vector<size_t> owner;
  for (size_t c = 0; c < copies; ++c) {
    const CollapseProposal& p = kernels_[c]->held();
    const Ring& fan = *p.fan;
    const int n = fan.neighbours();
    for (int f = 0; f < fan.faces; ++f) {
      if (p.IsDeleted(f)) continue;
      const int g = (f + 1) % n;
      const Triangle t{{ToD(fan.pos[p.target]), ToD(fan.pos[f]), ToD(fan.pos[g])},
                       {PointOf(p.vd()), PointOf(fan.nbr[f]), PointOf(fan.nbr[g])}};
      fresh.emplace_back(t);
      owner.push_back(c);
    }
  }
  for (size_t a = 0; a < fresh.size(); ++a)
    for (size_t b = a + 1; b < fresh.size(); ++b)
      if (owner[a] != owner[b] && fresh[a].box.Overlaps(fresh[b].box) &&
          OverlappingTrianglesIntersect(fresh[a], fresh[b]))
        return true;
  return false;
}

}  // namespace femsimp
