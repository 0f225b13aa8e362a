#include "server/call_watchdog.h"

#include <algorithm>

#include "absl/strings/str_format.h"

namespace femsimp::server {
namespace {

// How often the watched calls are checked: an expired one ends within this much of its limit.
constexpr auto kCheckEvery = std::chrono::milliseconds(50);

}  // namespace

CallWatchdog::CallWatchdog() : thread_([this] { Run(); }) {}

CallWatchdog::~CallWatchdog() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

CallWatchdog::Watch::Watch(CallWatchdog& watchdog, grpc::ServerContext* ctx,
                           const StreamLimits& limits)
    : watchdog_(watchdog) {
  if (limits.idle_seconds <= 0 && limits.deadline_seconds <= 0) return;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  const Clock::time_point now = Clock::now();
  entry_ = watchdog_.calls_.insert(watchdog_.calls_.end(), Entry{ctx, limits, now, now, ""});
  watched_ = true;
}

void CallWatchdog::Watch::Touch() {
  if (!watched_) return;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  entry_->last = Clock::now();
}

void CallWatchdog::Watch::Done() {
  if (!watched_) return;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  expired_ = entry_->expired;
  watchdog_.calls_.erase(entry_);
  watched_ = false;
}

std::string CallWatchdog::Watch::expired() const {
  if (!watched_) return expired_;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  return entry_->expired;
}

void CallWatchdog::Run() {
  std::unique_lock<std::mutex> lock(mu_);
  while (!stop_) {
    wake_.wait_for(lock, kCheckEvery);
    const Clock::time_point now = Clock::now();
    for (Entry& e : calls_) {
      if (!e.expired.empty()) continue;
      const StreamLimits& l = e.limits;
      const double idle = std::chrono::duration<double>(now - e.last).count();
      const double total = std::chrono::duration<double>(now - e.start).count();
      if (l.idle_seconds > 0 && idle > l.idle_seconds)
        e.expired = absl::StrFormat("%s idle for %.3g s: nothing went through within %g s (%s)",
                                    l.what, idle, l.idle_seconds, l.idle_flag);
      else if (l.deadline_seconds > 0 && total > l.deadline_seconds)
        e.expired = absl::StrFormat("%s not done after %.3g s (%s = %g)", l.what, total,
                                    l.deadline_flag, l.deadline_seconds);
      if (!e.expired.empty()) e.ctx->TryCancel();
    }
  }
}

}  // namespace femsimp::server
