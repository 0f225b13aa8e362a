#include "cellsim/work_plan.h"

#include <algorithm>

namespace femsimp::cellsim {

WorkPlan WorkPlan::PerSpe(std::vector<std::span<const uint32_t>> lists) {
  WorkPlan plan;
  plan.kind_ = Kind::kPerSpe;
  plan.lists_ = std::move(lists);
  return plan;
}

WorkPlan WorkPlan::Shared(uint64_t count, uint64_t chunk) {
  WorkPlan plan;
  plan.kind_ = Kind::kShared;
  plan.count_ = count;
  plan.chunk_ = std::max<uint64_t>(chunk, 1);
  return plan;
}

WorkPlan WorkPlan::Guided(uint64_t count, uint64_t max_chunk, const uint64_t* published_at) {
  WorkPlan plan;
  plan.kind_ = Kind::kGuided;
  plan.count_ = count;
  plan.chunk_ = std::max<uint64_t>(max_chunk, 1);
  plan.published_at_ = published_at;
  return plan;
}

void WorkCursor::Begin(const WorkPlan* plan, std::atomic<uint64_t>* shared_next,
                       GuidedDispenser* guided, int spe_index) {
  *this = WorkCursor();
  plan_ = plan;
  shared_next_ = shared_next;
  guided_ = guided;
  spe_index_ = spe_index;
  if (plan->kind() == WorkPlan::Kind::kPerSpe &&
      static_cast<size_t>(spe_index) < plan->lists().size()) {
    list_ = plan->lists()[spe_index];
    end_ = list_.size();
  }
}

std::optional<uint64_t> WorkCursor::Next(uint64_t elapsed, Visit* visit) {
  *visit = Visit{false, elapsed};
  if (plan_ == nullptr) return std::nullopt;
  switch (plan_->kind()) {
    case WorkPlan::Kind::kNone:
      return std::nullopt;
    case WorkPlan::Kind::kPerSpe:
      if (pos_ >= end_) return std::nullopt;
      return list_[pos_++];
    case WorkPlan::Kind::kShared:
      if (pos_ >= end_) {
        const uint64_t begin = shared_next_->fetch_add(plan_->chunk(), std::memory_order_relaxed);
        if (begin >= plan_->count()) return std::nullopt;
        visit->took_chunk = true;
        pos_ = begin;
        end_ = std::min(begin + plan_->chunk(), plan_->count());
      }
      return pos_++;
    case WorkPlan::Kind::kGuided:
      if (pos_ >= end_) {
        visit->took_chunk = true;
        const GuidedDispenser::Grant grant = guided_->Take(spe_index_, elapsed);
        pos_ = grant.first;
        end_ = grant.last;
        visit->served_at = grant.served_at;
        if (pos_ >= end_) return std::nullopt;
      } else {
        guided_->Progress(spe_index_, elapsed);
      }
      return pos_++;
  }
  return std::nullopt;
}

}  // namespace femsimp::cellsim
