// Retrying a whole Simplify job when another attempt can succeed: the replica that had the job
// went away (UNAVAILABLE), or the server's queue was full and it sent a retry pushback
// (RESOURCE_EXHAUSTED). A retry is a new call that uploads the job again; that is safe because a
// job has no effect besides its output, and the output only counts once it arrived whole.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>

#include "client/remote_call.h"

namespace femsimp::cli {

struct RetryPolicy {
  int max_attempts = 5;  // attempts in all; 1 means no retry
  std::chrono::milliseconds initial_backoff{250};
  std::chrono::milliseconds max_backoff{8000};
  double multiplier = 2.0;
  double jitter = 0.2;  // a backoff is scaled by a random factor in [1 - jitter, 1 + jitter]
};

// UNAVAILABLE: the server was unreachable, is shutting down, or the connection broke (a replica
// behind a balancer was killed). RESOURCE_EXHAUSTED only with a pushback >= 0: without one it is
// a server limit (mesh too large) that fails the same way on every attempt, and a negative
// pushback is the server saying "do not retry" (gRPC's retry design, A6).
bool IsRetryable(grpc::StatusCode code, std::optional<int> pushback_ms);

// The wait after attempt `failed_attempt` (counted from 1) failed. A server pushback replaces
// the backoff and is never shortened: jitter only lengthens it (by up to `jitter`), so clients
// pushed back together do not return together. Otherwise exponential backoff
// min(max_backoff, initial_backoff * multiplier^(failed_attempt - 1)), scaled by the jitter.
// `unit` is a uniform random number in [0, 1).
std::chrono::milliseconds RetryDelay(const RetryPolicy& policy, int failed_attempt,
                                     std::optional<int> pushback_ms, double unit);

// Lets another thread (a Ctrl-C watcher) cancel a job across its attempts: the running call,
// or the wait between two attempts.
class JobCanceller {
 public:
  void Cancel();
  bool cancelled() const;

  // Used by SimplifyWithRetry: the context of the running attempt (false: already cancelled),
  // and an interruptible wait (false: cancelled during it).
  bool Attach(grpc::ClientContext* ctx);
  void Detach();
  bool WaitFor(std::chrono::milliseconds d);

 private:
  mutable std::mutex mu_;
  std::condition_variable cv_;
  grpc::ClientContext* ctx_ = nullptr;
  bool cancelled_ = false;
};

struct RetryOptions {
  RetryPolicy policy;
  // Of the whole job, all attempts and waits included; none when unset.
  std::optional<std::chrono::system_clock::time_point> deadline;
  RemoteCallbacks callbacks;  // passed to every attempt
  bool keep_output = true;
  JobCanceller* canceller = nullptr;
  // The stub's channel. When given, after an UNAVAILABLE attempt and its wait, a channel that
  // is not connected is asked to reconnect at once and given up to one more wait to do so:
  // otherwise the next attempt fails at once on the stale connection state (here a restarted
  // replica went unused for over 8 s, every attempt failing).
  std::shared_ptr<grpc::Channel> channel;
  // Before each wait: the attempt that failed (from 1), its outcome, the wait.
  std::function<void(int, const RemoteOutcome&, std::chrono::milliseconds)> on_retry;
};

struct RetryCounters {
  int attempts = 0;
  int unavailable = 0;         // attempts that ended UNAVAILABLE
  int resource_exhausted = 0;  // attempts that ended RESOURCE_EXHAUSTED
  double waited_seconds = 0;   // backoff and pushback waits
};

// Runs RemoteSimplify until an attempt succeeds (its result and every mesh chunk arrived and
// assembled), fails with a status that is not retryable, the attempts are used up, or the next
// wait would pass the deadline. Returns the last attempt's outcome; when retries gave up, its
// message says after how many attempts. Adds to *counters when given.
RemoteOutcome SimplifyWithRetry(v1::Simplifier::Stub& stub, const v1::JobSpec& spec,
                                const RawMesh& mesh, const RetryOptions& options,
                                RetryCounters* counters = nullptr);

}  // namespace femsimp::cli
