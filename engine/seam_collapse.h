// Seams simplified along themselves (issue 12, item 2). A seam point of an assembly has one copy
// per sheet meeting there (engine/seams.h), every copy locked, so the parallel passes never move
// one copy alone. Between passes this stage slides whole seam points along their seam: a
// compound collapse moves every copy of point P onto the copy of the same seam neighbour D in its
// sheet, all or none. It is taken only if
//   - P is an inner point of one seam curve: in every sheet its copy is a boundary vertex whose
//     two boundary edges go to the same two points L and D (seam edges are boundary edges of
//     every sheet using them); junctions and curve ends stay;
//   - each copy's collapse passes every rule of the kernel, as a vertex sliding along its
//     boundary line (shape, topology, tolerance, fields, no intersection with the rest);
//   - the copies' new triangles do not intersect one another (they share the new seam edge L-D,
//     and touch there only: corners are named by point, as in the face index);
//   - no face anywhere already joins L and D (the merged seam edge would gain faces);
//   - the budgets accept all the copies' changes together (RuleSet::SpendBudgetsTogether).
// Every sheet then has the edge L-D where it had L-P-D, so the rejoined seam is the input's
// with P left out, and its face count is unchanged. The stage runs on the host, one compound at
// a time in point order, so its outcome depends on the mesh it starts from only: deterministic
// wherever the passes are, and the same on both back ends.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/face_grid.h"
#include "engine/kernel.h"
#include "engine/mesh.h"
#include "engine/point_copies.h"
#include "engine/port.h"
#include "engine/rule.h"

namespace femsimp {

class SeamCollapser {
 public:
  // copies: the mesh's seam points (the run's, which the rules read too). grid: the
  // self-intersection rule's face index, or nullptr when that rule is off. requeue_changed: as
  // the kernel's (RemovalKernel).
  SeamCollapser(Mesh& mesh, const PointCopies& copies, const RuleSet& rules, bool quadric,
                FaceGrid* grid, bool requeue_changed = false);
  ~SeamCollapser();

  // Whether the mesh has seam points (copies of one point, locked) at all.
  bool empty() const { return copies_.empty(); }

  struct SweepResult {
    uint64_t points = 0;    // seam points removed
    uint64_t vertices = 0;  // mesh vertices removed (every copy of each point)
    bool budget_spent = false;
    std::vector<uint32_t> requeued;  // as KernelStats::requeued, for the next selection
  };
  // Tries every seam point once (nothing else may run on the mesh meanwhile).
  SweepResult Sweep(RemovalBudget& budget);

 private:
  enum class Tried { kRemoved, kRefused, kBudgetSpent };
  // One seam point (index into copies_), onto its seam neighbour `onto` (a point id), `left`
  // the one left behind; rings_ hold its copies' fans.
  Tried TryCompound(size_t point, uint32_t onto, uint32_t left, RemovalBudget& budget);
  // The vertices of point p: its copies, or the one vertex `fallback` when it has none.
  std::vector<uint32_t> VerticesOf(uint32_t p, uint32_t fallback) const;
  bool AnyFaceJoins(uint32_t a_point, uint32_t a_vertex, uint32_t b_point);
  bool NewTrianglesMeet(size_t copies) const;
  uint32_t PointOf(uint32_t v) const { return copies_.PointOf(v); }

  Mesh& mesh_;
  const RuleSet& rules_;
  const bool quadric_;
  const bool requeue_changed_;
  FaceGrid* grid_;
  const PointCopies& copies_;
  NativePort port_;
  // Per copy of the compound being tried.
  std::vector<Ring> rings_;
  std::vector<uint32_t> targets_, replaced_;
  std::vector<std::unique_ptr<NativePort>> ports_;
  std::vector<std::unique_ptr<RemovalKernel<NativePort>>> kernels_;
  std::vector<CollapseDelta> deltas_;
  KernelStats scratch_stats_;
  RemovalBudget no_budget_;  // the kernels' own (unused: the sweep reserves removals itself)
};

}  // namespace femsimp
