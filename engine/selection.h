// A pass's selection (paper section 3: cost, sort): every removable vertex with its cost, in
// cost order.
//
// The first pass looks at every vertex. Later passes look only at the vertices that can be
// removable then: the last pass's selection (each one removed, refused, or still removable),
// the refused vertices the kernels made removable again (KernelStats::requeued), and the
// vertices refused with a retry due (kRetryBit) that no reconsideration has retried yet. A
// vertex becomes removable, or due a retry, in no other way (only a candidate is refused), so
// the selection is the one a scan of every vertex would make, at a cost that follows the pass's
// work instead of the mesh's size: a late pass of a sliver mesh has a few thousand candidates
// among millions of vertices. Runs whose reconsideration retries every refused vertex
// (SimplifyOptions::periodic_retry) scan every vertex each pass.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "engine/cost.h"
#include "engine/mesh.h"
#include "engine/work_shares.h"
#include "engine/worker_pool.h"

namespace femsimp {

class CandidateSelection {
 public:
  // scatter: the deterministic rounds' order (costs bucketed, ties by a scramble of the id);
  // retry_all: reconsideration makes every refused vertex removable again.
  CandidateSelection(Mesh& mesh, WorkerPool& pool, const VertexCost& cost, bool scatter,
                     bool retry_all);

  // The removable vertices in cost order; on a reconsideration pass the refused vertices due a
  // retry become removable first. Once `cancelled` (polled every few thousand vertices) says
  // true, a partial order. Adds the contexts' working time to *busy_seconds.
  std::vector<uint32_t> Select(bool reconsider, const std::function<bool()>& cancelled,
                               double* busy_seconds);

  // The vertices the last Select looked at (every vertex slot, on a scan), and whether it
  // merged a list of them rather than scanning every slot (the cell back end's cost model).
  size_t looked() const { return looked_; }
  bool merged() const { return merged_; }

  // Where the pass's contexts leave the vertices they made removable again (the back ends and
  // the seam sweep append their kernels' KernelStats::requeued).
  std::vector<uint32_t>* requeued() { return &requeued_; }

 private:
  // The vertices to look at this pass, each once, in vertex order.
  std::vector<uint32_t> Watched();

  Mesh& mesh_;
  WorkerPool& pool_;
  const VertexCost& cost_;
  const bool scatter_;
  const bool retry_all_;
  size_t looked_ = 0;
  bool merged_ = false;
  bool scan_all_ = true;            // until the first selection, and always with retry_all
  std::vector<uint32_t> watched_;   // the last selection and the refused ones awaiting a retry
  std::vector<uint32_t> requeued_;  // since the last selection, duplicates allowed
  std::vector<uint64_t> seen_;      // a bit per vertex, while Watched merges (0 between calls)
  WorkShares shares_;               // the vertices to cost, over the pool's contexts
};

}  // namespace femsimp
