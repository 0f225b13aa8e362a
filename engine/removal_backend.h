// A back end runs the removal phase of a pass: the sorted candidates, split uniformly over its
// contexts (candidate i goes to context i mod N, so every context works in cost order; the cell
// back end gives each SPE a region of the mesh instead, still in cost order; or in contiguous
// blocks, RemovalPhase::blocks), each context running the one candidate loop (RunCandidates)
// through the back end's memory port. The back end supplies memory access (the port), locking (the
// port's status words) and scheduling (threads, or SPEs and their software threads); the loop and
// the kernel are shared.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "engine/face_grid.h"
#include "engine/kernel.h"
#include "engine/mesh.h"
#include "engine/rule.h"
#include "engine/simplify.h"
#include "engine/worker_pool.h"

namespace femsimp {

// What every context's kernel runs with.
struct KernelConfig {
  const RuleSet* rules = nullptr;
  bool quadric = false;         // quadric cost: rank directions by it, Vd absorbs V's quadric
  bool placement = false;       // full-edge collapses where both ends may move (engine/star.h)
  bool requeue_changed = true;  // a refused vertex whose fan a collapse changes is removable again
};

// Every context polls the caller's cancellation every this many candidates (a few
// milliseconds of work at most, on either back end).
inline constexpr size_t kCancelPollInterval = 32;

struct RemovalPhase {
  const uint32_t* candidates;  // vertex ids in cost order
  size_t count;
  size_t sorted;  // removable vertices sorted this pass (candidates are the first `count`)
  RemovalBudget* budget;
  std::atomic<bool>* stop;                 // set on cancellation or a spent budget
  const std::function<bool()>* cancelled;  // thread-safe: every context polls it
  // Deterministic rounds (engine/rounds.h) run a pass as several removal phases.
  bool pass_start = true;  // the first of its pass (the cell model charges cost and sort)
  size_t claimed = 0;      // candidates whose claims the round checked (cell model)
  // Rounds: each candidate's place in the round's window, i.e. in the order the winners were
  // picked (the cell model hands them over as they are picked). May be null.
  const uint32_t* window_rank = nullptr;
  bool fresh_caches = false;  // nothing cached may predate the last phase's writes
  // Each context takes a contiguous block of the candidates instead of every N-th one: the
  // rounds hand over their winners by vertex number, so a block is close in memory. (Natively,
  // a context done with its block takes chunks from the back of the others': engine/work_shares.h.)
  bool blocks = false;
  // Rounds: each candidate's fan box and the face index, whose cells a native context hints
  // ahead of the candidate's hold (FaceGrid::PrefetchSlots, PrefetchLists). May be null.
  const FaceGrid::Box* boxes = nullptr;
  const FaceGrid* grid = nullptr;
  // The pass's removable vertices in the order sorted (`sorted` of them): the cell back end
  // sorts them again on its SPEs, to model that sort's cost from the work it does.
  const uint32_t* order = nullptr;
  // What the pass's selection did (the cell back end's model charges it): the vertices it
  // looked at, costing the removable ones, and of those the ones it merged from lists (on the
  // PPE) rather than scanned in vertex order.
  size_t looked = 0, merged = 0;
  // Where the contexts' KernelStats::requeued go once the phase is over (may be null).
  std::vector<uint32_t>* requeued = nullptr;
  // Where the contexts' KernelStats::changed go (may be null: dropped).
  std::vector<uint32_t>* changed = nullptr;

  bool Stopped() const {
    return stop->load(std::memory_order_relaxed) || budget->stop.load(std::memory_order_relaxed);
  }
  // True (and every context stops) once the caller has cancelled.
  bool PollCancelled() const {
    if (!*cancelled || !(*cancelled)()) return false;
    stop->store(true, std::memory_order_relaxed);
    return true;
  }
};

// The candidate loop of one context, the same on every back end: `next` yields the context's
// candidates in cost order, then nullopt. Ends early on cancellation or a spent budget.
template <class Port, class Next>
void RunCandidates(RemovalKernel<Port>& kernel, const RemovalPhase& phase, Next&& next) {
  for (size_t visited = 0;; ++visited) {
    if (phase.Stopped()) return;
    if (visited % kCancelPollInterval == 0 && phase.PollCancelled()) return;
    const std::optional<uint32_t> v = next();
    if (!v) return;
    if (kernel.TryRemove(*v) == Outcome::kBudgetSpent) return;
  }
}

class RemovalBackend {
 public:
  virtual ~RemovalBackend() = default;
  virtual int contexts() const = 0;
  // Fills tried/removed/conflicts/inconsistent/rejections/busy_seconds (and the cell counters).
  virtual absl::Status RunRemoval(const RemovalPhase& phase, PassStats& stats) = 0;
};

std::unique_ptr<RemovalBackend> MakeNativeBackend(Mesh& mesh, const KernelConfig& kernel,
                                                  WorkerPool& pool);

// Emulated Cell BE: fails when the local store cannot hold the cache and thread stacks.
absl::StatusOr<std::unique_ptr<RemovalBackend>> MakeCellBackend(Mesh& mesh,
                                                                const KernelConfig& kernel,
                                                                const CellOptions& options);

// The contexts' counters for a phase, recording what the phase asks for.
std::vector<KernelStats> ContextStats(const RemovalPhase& phase, int contexts);
// Adds a context's counters to the pass's, and moves its requeued and changed vertices to the
// phase's lists.
void AddKernelStats(KernelStats& k, const RemovalPhase& phase, PassStats& stats);

}  // namespace femsimp
