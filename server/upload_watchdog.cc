#include "server/upload_watchdog.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "server/log.h"

namespace femsimp::server {

UploadWatchdog::UploadWatchdog(double idle_seconds, double deadline_seconds)
    : idle_(idle_seconds), deadline_(deadline_seconds) {
  if (idle_ > 0 || deadline_ > 0) thread_ = std::thread([this] { Run(); });
}

UploadWatchdog::~UploadWatchdog() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

UploadWatchdog::Upload::Upload(UploadWatchdog& watchdog, grpc::ServerContext* ctx)
    : watchdog_(watchdog) {
  if (!watchdog_.thread_.joinable()) return;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  const Clock::time_point now = Clock::now();
  entry_ = watchdog_.uploads_.insert(watchdog_.uploads_.end(), Entry{ctx, now, now, ""});
  watched_ = true;
}

void UploadWatchdog::Upload::Touch() {
  if (!watched_) return;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  entry_->last = Clock::now();
}

void UploadWatchdog::Upload::Done() {
  if (!watched_) return;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  expired_ = entry_->expired;
  watchdog_.uploads_.erase(entry_);
  watched_ = false;
}

std::string UploadWatchdog::Upload::expired() const {
  if (!watched_) return expired_;
  std::lock_guard<std::mutex> lock(watchdog_.mu_);
  return entry_->expired;
}

void UploadWatchdog::Run() {
  // Checked a few times per limit: a stalled upload ends within about a quarter of its limit.
  const double shortest =
      std::min(idle_ > 0 ? idle_ : deadline_, deadline_ > 0 ? deadline_ : idle_);
  const auto every = std::chrono::duration<double>(std::clamp(shortest / 4, 0.01, 1.0));
  std::unique_lock<std::mutex> lock(mu_);
  while (!stop_) {
    wake_.wait_for(lock, every);
    const Clock::time_point now = Clock::now();
    for (Entry& e : uploads_) {
      if (!e.expired.empty()) continue;
      const double idle = std::chrono::duration<double>(now - e.last).count();
      const double total = std::chrono::duration<double>(now - e.start).count();
      if (idle_ > 0 && idle > idle_)
        e.expired = absl::StrFormat(
            "upload idle for %.3g s: no message within %g s (--upload_idle_seconds)", idle, idle_);
      else if (deadline_ > 0 && total > deadline_)
        e.expired = absl::StrFormat("upload not done after %.3g s (--upload_deadline_seconds = %g)",
                                    total, deadline_);
      if (!e.expired.empty()) e.ctx->TryCancel();
    }
  }
}

}  // namespace femsimp::server
