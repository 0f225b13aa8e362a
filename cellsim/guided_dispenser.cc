#include "cellsim/guided_dispenser.h"

#include <algorithm>

namespace femsimp::cellsim {

void GuidedDispenser::Begin(int spes, uint64_t count, uint64_t visit_cycles, uint64_t max_chunk,
                            const uint64_t* published_at) {
  std::lock_guard<std::mutex> lock(mu_);
  while (slots_.size() < static_cast<size_t>(spes)) slots_.push_back(std::make_unique<Slot>());
  slots_.resize(spes);
  for (auto& slot : slots_) {
    slot->state = State::kWorking;
    slot->progress.store(0, std::memory_order_relaxed);
  }
  waiting_.store(0, std::memory_order_relaxed);
  next_ = 0;
  count_ = count;
  visit_cycles_ = visit_cycles;
  max_chunk_ = max_chunk;
  published_at_ = published_at;
}

GuidedDispenser::Grant GuidedDispenser::Take(int spe, uint64_t elapsed) {
  std::unique_lock<std::mutex> lock(mu_);
  Slot& slot = *slots_[spe];
  // Once every item is taken, the order of the requests no longer matters.
  if (next_ >= count_) return Grant{count_, count_, elapsed};
  slot.state = State::kWaiting;
  slot.asked_at = elapsed;
  slot.progress.store(elapsed, std::memory_order_relaxed);
  waiting_.fetch_add(1, std::memory_order_relaxed);
  ServeLocked();
  slot.wake.wait(lock, [&] { return slot.state == State::kServed; });
  slot.state = State::kWorking;
  return slot.grant;
}

void GuidedDispenser::GiveLocked(Slot& slot) {
  // Served when it asked, or when the next item is published if that is later; it cannot ask
  // again before its visit is paid for, so the next in line (asking at the same cycle, say)
  // need not wait for it to report progress.
  const uint64_t at = std::max(slot.asked_at, PublishedAt(next_));
  slot.progress.store(at + visit_cycles_, std::memory_order_relaxed);
  uint64_t last = next_ + ChunkSize(count_ - next_, static_cast<int>(slots_.size()), max_chunk_);
  last = std::min(count_, last);
  if (published_at_ != nullptr)  // only what is published by then
    last = static_cast<uint64_t>(
        std::upper_bound(published_at_ + next_ + 1, published_at_ + last, at) - published_at_);
  slot.grant = Grant{next_, last, at};
  next_ = last;
  slot.state = State::kServed;
  waiting_.fetch_sub(1, std::memory_order_relaxed);
  slot.wake.notify_one();
  if (next_ < count_) return;
  // Those still waiting learn that nothing is left, in any order.
  for (auto& other : slots_)
    if (other->state == State::kWaiting) {
      other->grant = Grant{count_, count_, other->asked_at};
      other->state = State::kServed;
      waiting_.fetch_sub(1, std::memory_order_relaxed);
      other->wake.notify_one();
    }
}

void GuidedDispenser::Progress(int spe, uint64_t elapsed) {
  slots_[spe]->progress.store(elapsed, std::memory_order_relaxed);
  if (waiting_.load(std::memory_order_relaxed) == 0) return;
  std::lock_guard<std::mutex> lock(mu_);
  ServeLocked();
}

void GuidedDispenser::Finish(int spe) {
  std::lock_guard<std::mutex> lock(mu_);
  if (static_cast<size_t>(spe) >= slots_.size()) return;
  Slot& slot = *slots_[spe];
  if (slot.state != State::kWorking) return;
  slot.state = State::kDone;
  ServeLocked();
}

void GuidedDispenser::ServeLocked() {
  for (;;) {
    int earliest = -1;
    for (size_t i = 0; i < slots_.size(); ++i)
      if (slots_[i]->state == State::kWaiting &&
          (earliest < 0 || slots_[i]->asked_at < slots_[earliest]->asked_at))
        earliest = static_cast<int>(i);
    if (earliest < 0) return;
    const uint64_t at = slots_[earliest]->asked_at;
    // A working SPE (or one served, not yet back at work) may still ask at its progress or
    // later: it must be past `at`, or at it with a higher index.
    for (size_t i = 0; i < slots_.size(); ++i) {
      const State state = slots_[i]->state;
      if (state != State::kWorking && state != State::kServed) continue;
      const uint64_t p = slots_[i]->progress.load(std::memory_order_relaxed);
      if (p < at || (p == at && static_cast<int>(i) < earliest)) return;
    }
    GiveLocked(*slots_[earliest]);
  }
}

}  // namespace femsimp::cellsim
