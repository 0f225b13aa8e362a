// Ends uploads that stall: no message for `idle` seconds, or not done after `deadline` seconds in
// all (issue 15: fifty stalled uploads once held every queue slot). The synchronous API's Read
// cannot time out, so one thread watches every upload and cancels an expired call
// (ServerContext::TryCancel): the handler's Read then fails, its queue slot is freed, and it
// records why (Upload::expired) in the job's status and the log. The client sees its call
// cancelled.
#pragma once

#include <chrono>
#include <condition_variable>
#include <list>
#include <mutex>
#include <string>
#include <thread>

#include "grpcpp/server_context.h"

namespace femsimp::server {

class UploadWatchdog {
 public:
  // 0 turns a limit off; with both off no thread runs.
  UploadWatchdog(double idle_seconds, double deadline_seconds);
  ~UploadWatchdog();
  UploadWatchdog(const UploadWatchdog&) = delete;
  UploadWatchdog& operator=(const UploadWatchdog&) = delete;

  using Clock = std::chrono::steady_clock;
  struct Entry {
    grpc::ServerContext* ctx;
    Clock::time_point start, last;
    std::string expired;  // why the watchdog cancelled it; empty: it did not
  };

  // One call's upload, watched from construction until Done() or destruction.
  class Upload {
   public:
    Upload(UploadWatchdog& watchdog, grpc::ServerContext* ctx);
    ~Upload() { Done(); }
    Upload(const Upload&) = delete;
    Upload& operator=(const Upload&) = delete;
    void Touch();  // a message arrived
    void Done();   // the upload is complete (or over): no longer watched
    // Why the watchdog cancelled the call, e.g. "upload idle for 30 s (--upload_idle_seconds)";
    // empty when it did not.
    std::string expired() const;

   private:
    UploadWatchdog& watchdog_;
    std::list<Entry>::iterator entry_;
    bool watched_ = false;
    std::string expired_;  // kept once Done
  };

 private:
  void Run();

  const double idle_, deadline_;
  mutable std::mutex mu_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::list<Entry> uploads_;  // guarded by mu_
  std::thread thread_;
};

}  // namespace femsimp::server
