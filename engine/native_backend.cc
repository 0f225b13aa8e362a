#include <chrono>
#include <vector>

#include "engine/port.h"
#include "engine/removal_backend.h"

namespace femsimp {

void AddKernelStats(const KernelStats& k, PassStats& stats) {
  stats.tried += k.tried;
  stats.removed += k.removed;
  stats.lock_conflicts += k.lock_conflicts;
  stats.inconsistent += k.inconsistent;
  for (size_t r = 0; r < k.rejections.size(); ++r) stats.rejections[r] += k.rejections[r];
}

namespace {

class NativeBackend final : public RemovalBackend {
 public:
  NativeBackend(Mesh& mesh, const CriteriaSet& criteria, const FidelityConfig& fidelity,
                WorkerPool& pool)
      : mesh_(mesh), criteria_(criteria), fidelity_(fidelity), pool_(pool) {}

  int contexts() const override { return pool_.size(); }

  absl::Status RunRemoval(const RemovalPhase& phase, PassStats& stats) override {
    const int n = pool_.size();
    std::vector<KernelStats> per_context(n);
    std::vector<double> busy(n, 0.0);
    pool_.Run([&](int c) {
      const auto start = std::chrono::steady_clock::now();
      NativePort port(mesh_);
      RemovalKernel<NativePort> kernel(port, criteria_, fidelity_, *phase.budget, per_context[c]);
      size_t visited = 0;
      for (size_t i = c; i < phase.count; i += n, ++visited) {
        if (phase.stop->load(std::memory_order_relaxed) ||
            phase.budget->stop.load(std::memory_order_relaxed))
          break;
        if (c == 0 && visited % kCancelPollInterval == 0 && *phase.cancelled &&
            (*phase.cancelled)()) {
          phase.stop->store(true, std::memory_order_relaxed);
          break;
        }
        if (kernel.TryRemove(phase.candidates[i]) == Outcome::kBudgetSpent) break;
      }
      busy[c] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    });
    for (int c = 0; c < n; ++c) {
      AddKernelStats(per_context[c], stats);
      stats.busy_seconds += busy[c];
    }
    return absl::OkStatus();
  }

 private:
  Mesh& mesh_;
  const CriteriaSet& criteria_;
  const FidelityConfig& fidelity_;
  WorkerPool& pool_;
};

}  // namespace

std::unique_ptr<RemovalBackend> MakeNativeBackend(Mesh& mesh, const CriteriaSet& criteria,
                                                  const FidelityConfig& fidelity,
                                                  WorkerPool& pool) {
  return std::make_unique<NativeBackend>(mesh, criteria, fidelity, pool);
}

}  // namespace femsimp
