#include <chrono>
#include <vector>

#include "engine/port.h"
#include "engine/removal_backend.h"
#include "engine/work_shares.h"

namespace femsimp {

std::vector<KernelStats> ContextStats(const RemovalPhase& phase, int contexts) {
  std::vector<KernelStats> stats(contexts);
  for (KernelStats& k : stats) k.record_changed = phase.changed != nullptr;
  return stats;
}

void AddKernelStats(KernelStats& k, const RemovalPhase& phase, PassStats& stats) {
  if (phase.requeued != nullptr)
    phase.requeued->insert(phase.requeued->end(), k.requeued.begin(), k.requeued.end());
  k.requeued.clear();
  if (phase.changed != nullptr)
    phase.changed->insert(phase.changed->end(), k.changed.begin(), k.changed.end());
  k.changed.clear();
  stats.tried += k.tried;
  stats.removed += k.removed;
  stats.placed += k.placed;
  stats.placed_on_lines += k.placed_on_lines;
  stats.lock_conflicts += k.lock_conflicts;
  stats.inconsistent += k.inconsistent;
  for (size_t r = 0; r < k.rejections.size(); ++r) stats.rejections[r] += k.rejections[r];
}

namespace {

// Candidates between a prefetch stage and its use (NativePort::PrefetchVertex, PrefetchFan).
constexpr size_t kPrefetchAhead = 4;
// Blocks are taken in chunks of at most this many candidates (engine/work_shares.h).
constexpr size_t kBlockChunk = 64;

class NativeBackend final : public RemovalBackend {
 public:
  NativeBackend(Mesh& mesh, const KernelConfig& kernel, WorkerPool& pool)
      : mesh_(mesh), kernel_(kernel), pool_(pool), blocks_(pool.size()) {}

  int contexts() const override { return pool_.size(); }

  absl::Status RunRemoval(const RemovalPhase& phase, PassStats& stats) override {
    const int n = pool_.size();
    std::vector<KernelStats> per_context = ContextStats(phase, n);
    std::vector<double> busy(n, 0.0);
    if (phase.blocks) blocks_.Reset(phase.count);
    pool_.Run([&](int c) {
      const auto start = std::chrono::steady_clock::now();
      NativePort port(mesh_);
      RemovalKernel<NativePort> kernel(port, *kernel_.rules, kernel_.quadric, *phase.budget,
                                       per_context[c], kernel_.placement, kernel_.requeue_changed);
      // Blocks: a winner's outcome does not depend on which context runs it, so a context done
      // with its block helps with the others' (a round waits for its slowest context).
      size_t next = c, end = phase.count, step = n;
      if (phase.blocks) next = end = 0, step = 1;
      RunCandidates(kernel, phase, [&]() -> std::optional<uint32_t> {
        if (next >= end && !(phase.blocks && blocks_.Next(c, kBlockChunk, &next, &end)))
          return std::nullopt;
        const size_t far = next + 2 * kPrefetchAhead * step, near = next + kPrefetchAhead * step;
        if (far < phase.count) {
          port.PrefetchVertex(phase.candidates[far]);
          if (phase.grid != nullptr) phase.grid->PrefetchSlots(phase.boxes[far]);
        }
        if (near < phase.count) {
          port.PrefetchFan(phase.candidates[near]);
          if (phase.grid != nullptr) phase.grid->PrefetchLists(phase.boxes[near]);
        }
        const uint32_t v = phase.candidates[next];
        next += step;
        return v;
      });
      busy[c] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    });
    for (int c = 0; c < n; ++c) {
      AddKernelStats(per_context[c], phase, stats);
      stats.busy_seconds += busy[c];
    }
    return absl::OkStatus();
  }

 private:
  Mesh& mesh_;
  const KernelConfig kernel_;
  WorkerPool& pool_;
  WorkShares blocks_;
};

}  // namespace

std::unique_ptr<RemovalBackend> MakeNativeBackend(Mesh& mesh, const KernelConfig& kernel,
                                                  WorkerPool& pool) {
  return std::make_unique<NativeBackend>(mesh, kernel, pool);
}

}  // namespace femsimp
