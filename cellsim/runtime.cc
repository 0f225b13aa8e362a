#include "cellsim/runtime.h"

#include <algorithm>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {

absl::StatusOr<std::unique_ptr<Runtime>> Runtime::Create(const RuntimeConfig& config) {
  if (config.num_spes < 1) {
    return absl::InvalidArgumentError(
        absl::StrFormat("runtime: need at least one SPE, got %d", config.num_spes));
  }
  std::unique_ptr<Runtime> rt(new Runtime(config));
  for (int i = 0; i < config.num_spes; ++i) {
    absl::StatusOr<std::unique_ptr<SpeContext>> spe =
        SpeContext::Create(i, config.num_spes, config.spe, &rt->memory_);
    if (!spe.ok()) return spe.status();
    rt->spes_.push_back(std::move(*spe));
  }
  for (int i = 0; i < config.num_spes; ++i) {
    rt->threads_.emplace_back([r = rt.get(), i] { r->Worker(i); });
  }
  return rt;
}

Runtime::~Runtime() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  start_cv_.notify_all();
  for (std::thread& t : threads_) t.join();
}

absl::Status Runtime::RegisterMainMemory(const void* base, size_t bytes, std::string name) {
  return memory_.Register(base, bytes, std::move(name));
}

absl::Status Runtime::UnregisterMainMemory(const void* base) { return memory_.Unregister(base); }

void Runtime::Worker(int index) {
  uint64_t seen = 0;
  for (;;) {
    const Kernel* kernel;
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      kernel = kernel_;
    }
    (*kernel)(*spes_[index]);
    guided_.Finish(index);  // (it may not have asked at all)
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (--pending_ == 0) done_cv_.notify_one();
    }
  }
}

uint64_t Runtime::StartCycles(RunStart start) const {
  const CostModel& cost = config_.spe.cost;
  switch (start) {
    case RunStart::kLaunch:
      return cost.spe_run_overhead_cycles;
    case RunStart::kResident:
      return cost.ResidentSyncCycles(num_spes());
    case RunStart::kHandOff:
      return cost.HandOffCycles();
  }
  return 0;
}

absl::Status Runtime::Run(const Kernel& kernel, const WorkPlan& plan, RunStart start_kind) {
  std::vector<uint64_t> start(spes_.size()), moved(spes_.size());
  shared_next_.store(0, std::memory_order_relaxed);
  const bool guided = plan.kind() == WorkPlan::Kind::kGuided;
  guided_.Begin(num_spes(), guided ? plan.count() : 0, config_.spe.cost.IndexVisitCycles(),
                plan.chunk(), guided ? plan.published_at() : nullptr);
  for (size_t i = 0; i < spes_.size(); ++i) {
    start[i] = spes_[i]->Now();
    moved[i] = spes_[i]->counters().DmaBytes();
    spes_[i]->BeginRun(&plan, &shared_next_, &guided_);
  }
  {
    std::unique_lock<std::mutex> lock(mu_);
    kernel_ = &kernel;
    pending_ = num_spes();
    ++generation_;
    start_cv_.notify_all();
    done_cv_.wait(lock, [&] { return pending_ == 0; });
    kernel_ = nullptr;
  }
  uint64_t slowest = 0, bytes = 0;
  absl::Status first_error;
  for (size_t i = 0; i < spes_.size(); ++i) {
    spes_[i]->EndRun();
    slowest = std::max(slowest, spes_[i]->Now() - start[i]);
    bytes += spes_[i]->counters().DmaBytes() - moved[i];
    const absl::Status& e = spes_[i]->error();
    if (first_error.ok() && !e.ok()) {
      first_error = absl::Status(e.code(), absl::StrFormat("SPE %d: %s", i, e.message()));
    }
  }
  // Each SPE's channel times its own transfers; together they share main memory's bandwidth.
  const uint64_t memory = config_.spe.cost.MemoryCycles(bytes, num_spes());
  if (memory > slowest) ++memory_bound_runs_;
  last_run_cycles_ = StartCycles(start_kind) + std::max(slowest, memory);
  spe_run_cycles_ += last_run_cycles_;
  ++runs_;
  return first_error;
}

SpeCounters Runtime::TotalCounters() const {
  SpeCounters total;
  for (const auto& spe : spes_) total += spe->counters();
  return total;
}

void Runtime::ResetCounters() {
  for (auto& spe : spes_) spe->counters().Reset();
  ppe_cycles_ = 0;
  spe_run_cycles_ = 0;
  last_run_cycles_ = 0;
}

}  // namespace femsimp::cellsim
