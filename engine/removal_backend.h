// A back end runs the removal phase of a pass: the sorted candidates, split uniformly over its
// contexts (candidate i goes to context i mod N, so every context works in cost order), each
// context running RemovalKernel through the back end's memory port.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>

#include "engine/criteria.h"
#include "engine/fidelity.h"
#include "engine/kernel.h"
#include "engine/mesh.h"
#include "engine/simplify.h"
#include "engine/worker_pool.h"

namespace femsimp {

struct RemovalPhase {
  const uint32_t* candidates;  // vertex ids in cost order
  size_t count;
  size_t sorted;  // removable vertices sorted this pass (candidates are the first `count`)
  RemovalBudget* budget;
  std::atomic<bool>* stop;                 // set on cancellation or a spent budget
  const std::function<bool()>* cancelled;  // polled by context 0 only
};

class RemovalBackend {
 public:
  virtual ~RemovalBackend() = default;
  virtual int contexts() const = 0;
  // Fills tried/removed/conflicts/inconsistent/rejections/busy_seconds (and the cell counters).
  virtual absl::Status RunRemoval(const RemovalPhase& phase, PassStats& stats) = 0;
};

std::unique_ptr<RemovalBackend> MakeNativeBackend(Mesh& mesh, const CriteriaSet& criteria,
                                                  const FidelityConfig& fidelity, WorkerPool& pool);

// Emulated Cell BE: fails when the local store cannot hold the cache and thread stacks.
absl::StatusOr<std::unique_ptr<RemovalBackend>> MakeCellBackend(Mesh& mesh,
                                                                const CriteriaSet& criteria,
                                                                const FidelityConfig& fidelity,
                                                                const CellOptions& options);

// Adds one context's kernel counters into the pass statistics.
void AddKernelStats(const KernelStats& k, PassStats& stats);

// Context 0 polls the caller's cancellation every this many candidates.
inline constexpr size_t kCancelPollInterval = 256;

}  // namespace femsimp
