#include "client/retry.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "absl/strings/str_cat.h"

namespace femsimp::cli {
namespace {

double UnitRandom() {
  thread_local std::mt19937_64 rng{std::random_device{}()};
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

grpc::Status WithNote(const grpc::Status& s, const std::string& note) {
  return grpc::Status(s.error_code(), absl::StrCat(s.error_message(), " (", note, ")"));
}

}  // namespace

bool IsRetryable(grpc::StatusCode code, std::optional<int> pushback_ms) {
  if (code == grpc::StatusCode::UNAVAILABLE) return true;
  if (code == grpc::StatusCode::RESOURCE_EXHAUSTED) return pushback_ms && *pushback_ms >= 0;
  return false;
}

std::chrono::milliseconds RetryDelay(const RetryPolicy& policy, int failed_attempt,
                                     std::optional<int> pushback_ms, double unit) {
  const double jitter = std::clamp(policy.jitter, 0.0, 1.0);
  unit = std::clamp(unit, 0.0, 1.0);
  if (pushback_ms && *pushback_ms >= 0) {
    return std::chrono::milliseconds(
        static_cast<long long>(std::ceil(*pushback_ms * (1.0 + jitter * unit))));
  }
  const double cap = static_cast<double>(policy.max_backoff.count());
  double backoff = static_cast<double>(policy.initial_backoff.count()) *
                   std::pow(std::max(1.0, policy.multiplier), std::max(0, failed_attempt - 1));
  backoff = std::min(backoff, cap) * (1.0 - jitter + 2.0 * jitter * unit);
  return std::chrono::milliseconds(static_cast<long long>(std::llround(backoff)));
}

void JobCanceller::Cancel() {
  std::lock_guard<std::mutex> lock(mu_);
  cancelled_ = true;
  if (ctx_) ctx_->TryCancel();
  cv_.notify_all();
}

bool JobCanceller::cancelled() const {
  std::lock_guard<std::mutex> lock(mu_);
  return cancelled_;
}

bool JobCanceller::Attach(grpc::ClientContext* ctx) {
  std::lock_guard<std::mutex> lock(mu_);
  if (cancelled_) return false;
  ctx_ = ctx;
  return true;
}

void JobCanceller::Detach() {
  std::lock_guard<std::mutex> lock(mu_);
  ctx_ = nullptr;
}

bool JobCanceller::WaitFor(std::chrono::milliseconds d) {
  std::unique_lock<std::mutex> lock(mu_);
  return !cv_.wait_for(lock, d, [&] { return cancelled_; });
}

RemoteOutcome SimplifyWithRetry(v1::Simplifier::Stub& stub, const v1::JobSpec& spec,
                                const RawMesh& mesh, const RetryOptions& options,
                                RetryCounters* counters) {
  RetryCounters local;
  RetryCounters& c = counters ? *counters : local;
  const int max_attempts = std::max(1, options.policy.max_attempts);
  const grpc::Status cancelled(grpc::StatusCode::CANCELLED, "cancelled by the client");
  for (int attempt = 1;; ++attempt) {
    RemoteOutcome out;
    grpc::ClientContext ctx;
    if (options.deadline) ctx.set_deadline(*options.deadline);
    if (options.canceller && !options.canceller->Attach(&ctx)) {
      out.status = cancelled;
      return out;
    }
    ++c.attempts;
    out = RemoteSimplify(stub, ctx, spec, mesh, options.callbacks, options.keep_output);
    if (options.canceller) options.canceller->Detach();

    const grpc::StatusCode code = out.status.error_code();
    if (code == grpc::StatusCode::UNAVAILABLE) ++c.unavailable;
    if (code == grpc::StatusCode::RESOURCE_EXHAUSTED) ++c.resource_exhausted;
    if (out.status.ok() || !IsRetryable(code, out.retry_pushback_ms)) return out;
    if (attempt >= max_attempts) {
      if (max_attempts > 1)
        out.status = WithNote(out.status, absl::StrCat("gave up after ", attempt, " attempts"));
      return out;
    }
    const std::chrono::milliseconds delay =
        RetryDelay(options.policy, attempt, out.retry_pushback_ms, UnitRandom());
    if (options.deadline && std::chrono::system_clock::now() + delay >= *options.deadline) {
      out.status = WithNote(
          out.status,
          absl::StrCat("attempt ", attempt, "; no time left to retry before the deadline"));
      return out;
    }
    if (options.on_retry) options.on_retry(attempt, out, delay);
    c.waited_seconds += std::chrono::duration<double>(delay).count();
    if (options.canceller) {
      if (!options.canceller->WaitFor(delay)) {
        out.status = cancelled;
        return out;
      }
    } else {
      std::this_thread::sleep_for(delay);
    }
    // A call fails at once while its channel is down, and gRPC only reconnects an idle channel
    // when asked: ask now (dropping its own backoff), and give the connection up to one more
    // backoff to come up, so the next attempt finds a replica that is back.
    if (options.channel && code == grpc::StatusCode::UNAVAILABLE &&
        options.channel->GetState(true) != GRPC_CHANNEL_READY) {
      grpc::experimental::ChannelResetConnectionBackoff(options.channel.get());
      auto until = std::chrono::system_clock::now() + delay;
      if (options.deadline) until = std::min(until, *options.deadline);
      auto t0 = std::chrono::steady_clock::now();
      options.channel->WaitForConnected(until);
      c.waited_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  }
}

}  // namespace femsimp::cli
