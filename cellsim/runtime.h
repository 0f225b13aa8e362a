#ifndef FEMSIMP_CELLSIM_RUNTIME_H_
#define FEMSIMP_CELLSIM_RUNTIME_H_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "cellsim/counters.h"
#include "cellsim/main_memory.h"
#include "cellsim/spe_context.h"
#include "cellsim/work_plan.h"

namespace femsimp::cellsim {

// How a run begins: kLaunch starts the SPE contexts and joins them at its end
// (spe_run_overhead_cycles); kResident wakes a program a launch left running, which reports
// back when done (CostModel::ResidentSyncCycles); kHandOff goes on from the work the SPEs
// just did, without a word from the PPE: each SPE tells the PPE through a word in main memory
// that its last share is done and goes on to the next run's (CostModel::HandOffCycles). The
// caller keeps the program resident and knows what hands off: the runtime cannot tell one
// program from another.
enum class RunStart { kLaunch, kResident, kHandOff };

struct RuntimeConfig {
  int num_spes = 8;
  SpeConfig spe;
};

// The PPE side: N SPE contexts, each on its own persistent host thread (created once, parked
// on a condition variable between runs, so a run costs a wake-up and a join, not thread
// creation). Run() starts the kernel on every SPE and returns when all have finished.
//
// Modeled time: the SPEs run in parallel, so a run lasts its start's cost (StartCycles) plus
// the largest number of cycles any SPE's clock advanced during it, or, when longer, the time
// main memory takes to move every byte their DMA moved (CostModel::memory_bytes_per_cycle);
// sequential PPE work (sorting, bookkeeping between passes) is added with AddPpeCycles.
// ElapsedCycles() is the sum.
//
// Not thread-safe: one PPE thread drives it. Kernels must not call Run.
class Runtime {
 public:
  using Kernel = std::function<void(SpeContext&)>;

  static absl::StatusOr<std::unique_ptr<Runtime>> Create(const RuntimeConfig& config);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  // Makes [base, base + bytes) reachable by the SPEs (see MainMemory). Between runs only.
  absl::Status RegisterMainMemory(const void* base, size_t bytes, std::string name);
  absl::Status UnregisterMainMemory(const void* base);
  const MainMemory& main_memory() const { return memory_; }

  // Runs `kernel` on every SPE with work from `plan`; returns the first error an SPE reported
  // (SpeContext::ReportError), prefixed with its index.
  absl::Status Run(const Kernel& kernel, const WorkPlan& plan = WorkPlan::None(),
                   RunStart start = RunStart::kLaunch);
  // What a run's start and end cost, without its work.
  uint64_t StartCycles(RunStart start) const;

  int num_spes() const { return static_cast<int>(spes_.size()); }
  SpeContext& spe(int i) { return *spes_[i]; }
  const SpeContext& spe(int i) const { return *spes_[i]; }

  void AddPpeCycles(uint64_t n) { ppe_cycles_ += n; }
  uint64_t ppe_cycles() const { return ppe_cycles_; }
  uint64_t last_run_cycles() const { return last_run_cycles_; }  // Start + slowest SPE.
  uint64_t ElapsedCycles() const { return spe_run_cycles_ + ppe_cycles_; }
  uint64_t runs() const { return runs_; }
  // Runs that main memory's bandwidth made longer than their slowest SPE.
  uint64_t memory_bound_runs() const { return memory_bound_runs_; }

  // Sum of all SPEs' counters (cycle fields: total SPE work, not elapsed time).
  SpeCounters TotalCounters() const;
  // Resets every SPE's counters and the PPE / elapsed cycle totals (e.g. per pass).
  void ResetCounters();

 private:
  explicit Runtime(const RuntimeConfig& config) : config_(config) {}
  void Worker(int index);

  RuntimeConfig config_;
  MainMemory memory_;
  std::vector<std::unique_ptr<SpeContext>> spes_;
  std::vector<std::thread> threads_;

  std::mutex mu_;
  std::condition_variable start_cv_;
  std::condition_variable done_cv_;
  uint64_t generation_ = 0;  // Bumped to start a run.
  int pending_ = 0;          // SPEs still running the current kernel.
  bool stop_ = false;
  const Kernel* kernel_ = nullptr;
  std::atomic<uint64_t> shared_next_{0};
  GuidedDispenser guided_;

  uint64_t ppe_cycles_ = 0;
  uint64_t spe_run_cycles_ = 0;
  uint64_t last_run_cycles_ = 0;
  uint64_t runs_ = 0;
  uint64_t memory_bound_runs_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_RUNTIME_H_
