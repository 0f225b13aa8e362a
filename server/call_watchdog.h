// Ends streams that stall (issue 15: fifty stalled uploads once held every queue slot, and
// results nobody read held their meshes). The synchronous API's Read and Write cannot time out,
// so one thread watches every call in a watched phase and cancels one that expires
// (ServerContext::TryCancel): its Read or Write then fails, the handler lets go of its queue
// slot or its mesh, and records why (Watch::expired) in the job's status and the log. The client
// sees its call cancelled.
#pragma once

#include <chrono>
#include <condition_variable>
#include <list>
#include <mutex>
#include <string>
#include <thread>

#include "grpcpp/server_context.h"

namespace femsimp::server {

// A watched phase's limits (0: off) and the words its expiry is told in.
struct StreamLimits {
  double idle_seconds = 0;      // no message for this long
  double deadline_seconds = 0;  // not done after this long in all
  const char* what = "upload";  // "upload", "result"
  const char* idle_flag = "";
  const char* deadline_flag = "";
};

class CallWatchdog {
 public:
  CallWatchdog();
  ~CallWatchdog();
  CallWatchdog(const CallWatchdog&) = delete;
  CallWatchdog& operator=(const CallWatchdog&) = delete;

  using Clock = std::chrono::steady_clock;
  struct Entry {
    grpc::ServerContext* ctx;
    StreamLimits limits;
    Clock::time_point start, last;
    std::string expired;  // why the watchdog cancelled it; empty: it did not
  };

  // One call's phase, watched from construction until Done() or destruction (no limit set: not
  // watched at all).
  class Watch {
   public:
    Watch(CallWatchdog& watchdog, grpc::ServerContext* ctx, const StreamLimits& limits);
    ~Watch() { Done(); }
    Watch(const Watch&) = delete;
    Watch& operator=(const Watch&) = delete;
    void Touch();  // a message went through
    void Done();   // the phase is over: no longer watched
    // Why the watchdog cancelled the call, e.g. "upload idle for 30 s: ..."; empty when it did
    // not.
    std::string expired() const;

   private:
    CallWatchdog& watchdog_;
    std::list<Entry>::iterator entry_;
    bool watched_ = false;
    std::string expired_;  // kept once Done
  };

 private:
  void Run();

  mutable std::mutex mu_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::list<Entry> calls_;  // guarded by mu_
  std::thread thread_;
};

}  // namespace femsimp::server
