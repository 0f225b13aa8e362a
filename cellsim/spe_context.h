#ifndef FEMSIMP_CELLSIM_SPE_CONTEXT_H_
#define FEMSIMP_CELLSIM_SPE_CONTEXT_H_

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "cellsim/atomic_unit.h"
#include "cellsim/cost_model.h"
#include "cellsim/counters.h"
#include "cellsim/cycle_clock.h"
#include "cellsim/dma_engine.h"
#include "cellsim/local_store.h"
#include "cellsim/main_memory.h"
#include "cellsim/soft_threads.h"
#include "cellsim/software_cache.h"
#include "cellsim/spe_hooks.h"
#include "cellsim/work_plan.h"

namespace femsimp::cellsim {

struct SpeConfig {
  size_t local_store_bytes = LocalStore::kDefaultBytes;
  CacheConfig cache;
  size_t thread_stack_bytes = 16 * 1024;  // Per software thread, from the local store.
  CostModel cost;
};

// One emulated SPE: its local store, MFC (DmaEngine), software cache, atomic unit, software
// threads, counters and cycle clock. A kernel running on an SPE touches main memory only
// through these:
//   - reads: cache().Read / ReadValue (16-byte elements through the software cache);
//   - writes: dma().Put from a local-store buffer, straight to main memory;
//   - status words: atomic() (GetLlar/PutLlc/CompareAndSwap/PutLluc/Load).
// and charges its own work with AddComputeCycles. Everything here is used by the SPE's own
// host thread only; the PPE (Runtime) reads counters between runs.
class SpeContext final : public Waiter {
 public:
  // Allocates the local store and the cache in it; fails when the cache does not fit.
  static absl::StatusOr<std::unique_ptr<SpeContext>> Create(int index, int num_spes,
                                                            const SpeConfig& config,
                                                            const MainMemory* memory);
  SpeContext(const SpeContext&) = delete;
  SpeContext& operator=(const SpeContext&) = delete;

  int index() const { return index_; }
  int num_spes() const { return num_spes_; }
  const SpeConfig& config() const { return config_; }

  LocalStore& local_store() { return *ls_; }
  DmaEngine& dma() { return dma_; }
  SoftwareCache& cache() { return *cache_; }
  AtomicUnit& atomic() { return atomic_; }
  SpeCounters& counters() { return counters_; }
  const SpeCounters& counters() const { return counters_; }

  // Modeled cycle of this SPE (monotonic; not reset with the counters).
  uint64_t Now() const { return clock_.Now(); }
  // Charges SPU work of the kernel (arithmetic, branches, its own loads from the LS).
  void AddComputeCycles(uint64_t n) { clock_.AddCompute(n); }

  // Runs body(*this, i) on K software threads (i = 0..K-1, K = 1: no switching), each with a
  // thread_stack_bytes stack from the local store; returns when all have returned. Inside,
  // cache misses and DMA waits suspend the thread and resume another ready one. Threads share
  // the SPE's cache, DMA engine, atomic unit and work cursor; they are cooperative, so they
  // need no locks among themselves (but must not keep a Read pointer across a call that may
  // wait). Fails (ResourceExhausted) when the stacks do not fit in the local store.
  absl::Status RunThreads(int k, const std::function<void(SpeContext&, int)>& body);
  // Index of the running software thread (0 outside RunThreads) and their number (1 outside).
  int thread_index() const { return threads_.active() ? threads_.current() : 0; }
  int num_threads() const { return threads_.active() ? threads_.num_threads() : 1; }
  // Explicit switch to another ready software thread, e.g. after cache().TouchReport(ea)
  // returned false (the paper's pattern); no-op with one thread.
  void Yield() { threads_.Yield(); }

  // Waiter: suspends the current software thread (or stalls) until `cycle`.
  void WaitUntil(uint64_t cycle) override { threads_.WaitUntil(cycle); }

  // Next work item of the current run's WorkPlan, or nullopt when this SPE has no more.
  std::optional<uint64_t> NextWorkItem();

  // Records a kernel failure; Runtime::Run returns the first one (kernels return void).
  void ReportError(absl::Status status);
  const absl::Status& error() const { return error_; }

  // Used by Runtime around each run.
  void BeginRun(const WorkPlan* plan, std::atomic<uint64_t>* shared_next, GuidedDispenser* guided);
  void EndRun() { work_.End(); }

 private:
  SpeContext(int index, int num_spes, const SpeConfig& config, const MainMemory* memory,
             std::unique_ptr<LocalStore> ls);

  int index_;
  int num_spes_;
  SpeConfig config_;
  SpeCounters counters_;
  CycleClock clock_;
  std::unique_ptr<LocalStore> ls_;
  DmaEngine dma_;
  AtomicUnit atomic_;
  SoftThreadScheduler threads_;
  std::unique_ptr<SoftwareCache> cache_;
  WorkCursor work_;
  uint64_t run_start_ = 0;  // Now() when the current run began
  absl::Status error_;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_SPE_CONTEXT_H_
