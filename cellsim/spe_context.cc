#include "cellsim/spe_context.h"

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {

absl::StatusOr<std::unique_ptr<SpeContext>> SpeContext::Create(int index, int num_spes,
                                                               const SpeConfig& config,
                                                               const MainMemory* memory) {
  absl::StatusOr<std::unique_ptr<LocalStore>> ls = LocalStore::Create(config.local_store_bytes);
  if (!ls.ok()) return ls.status();
  std::unique_ptr<SpeContext> ctx(new SpeContext(index, num_spes, config, memory, std::move(*ls)));
  absl::StatusOr<std::unique_ptr<SoftwareCache>> cache =
      SoftwareCache::Create(ctx->config_.cache, ctx->ls_.get(), &ctx->dma_, memory, &ctx->clock_,
                            &ctx->counters_, &ctx->config_.cost, ctx.get());
  if (!cache.ok()) {
    return absl::Status(cache.status().code(),
                        absl::StrFormat("SPE %d: %s", index, cache.status().message()));
  }
  ctx->cache_ = std::move(*cache);
  ctx->dma_.set_put_observer(ctx->cache_.get());
  return ctx;
}

SpeContext::SpeContext(int index, int num_spes, const SpeConfig& config, const MainMemory* memory,
                       std::unique_ptr<LocalStore> ls)
    : index_(index),
      num_spes_(num_spes),
      config_(config),
      clock_(&counters_),
      ls_(std::move(ls)),
      dma_(ls_.get(), memory, &clock_, &counters_, &config_.cost, this),
      atomic_(memory, &clock_, &counters_, &config_.cost),
      threads_(ls_.get(), &clock_, &counters_, &config_.cost) {}

absl::Status SpeContext::RunThreads(int k, const std::function<void(SpeContext&, int)>& body) {
  absl::Status s = threads_.Run(k, config_.thread_stack_bytes,
                                [this, &body](int thread_index) { body(*this, thread_index); });
  if (!s.ok()) return absl::Status(s.code(), absl::StrFormat("SPE %d: %s", index_, s.message()));
  return s;
}

std::optional<uint64_t> SpeContext::NextWorkItem() {
  WorkCursor::Visit visit;
  std::optional<uint64_t> item = work_.Next(Now() - run_start_, &visit);
  if (visit.took_chunk) {
    clock_.WaitForWorkUntil(run_start_ + visit.served_at);
    clock_.AddAtomic(config_.cost.IndexVisitCycles());
  }
  if (item.has_value()) ++counters_.work_items;
  return item;
}

void SpeContext::ReportError(absl::Status status) {
  if (error_.ok() && !status.ok()) error_ = std::move(status);
}

void SpeContext::BeginRun(const WorkPlan* plan, std::atomic<uint64_t>* shared_next,
                          GuidedDispenser* guided) {
  work_.Begin(plan, shared_next, guided, index_);
  run_start_ = Now();
  error_ = absl::OkStatus();
}

}  // namespace femsimp::cellsim
