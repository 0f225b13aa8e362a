// One simplification job, shared by the handler of its Simplify call (SimplifierService), the
// JobRunner's worker that runs it, and the by-id queries (GetJob, ListJobs, CancelJob, shutdown).
//
// All mutable state is private and guarded by one mutex, taken only in job.cc: callers see state
// transitions and snapshots, never the lock. Life cycle:
//
//   kUploading --Enqueue--> kQueued --Start--> kRunning --Succeed/Finish--> kSucceeded | kFailed
//   any state not yet ended --Finish/FinishCancelled/Close--> kFailed | kCancelled
//
// The first end wins; later ones are no-ops. Who calls what:
//   the handler:  Enqueue, WaitForChange, TakeOutput, Close (always, when its call is over)
//   the runner:   Start, StartRemoval, AddPass, Succeed, Finish, FinishCancelled,
//                 queued_seconds, run_seconds
//   anyone:       RequestCancel, cancelled, cancel_status, Describe, the constant facts
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/mesh.h"
#include "engine/prepare.h"
#include "engine/simplify.h"
#include "fecheck/fe_check.h"
#include "femsimp/v1/femsimp.pb.h"
#include "grpcpp/support/status.h"

namespace femsimp::server {

enum class JobState { kUploading, kQueued, kRunning, kSucceeded, kFailed, kCancelled };
inline bool IsEnded(JobState s) {
  return s == JobState::kSucceeded || s == JobState::kFailed || s == JobState::kCancelled;
}

class Job {
 public:
  using Clock = std::chrono::steady_clock;

  // tenant: the caller's (server/auth.h; "" without tenants). fe_check: run the FE check on the
  // input and the output after the simplification.
  Job(std::string id, std::string label, SimplifyOptions options, uint64_t vertices, uint64_t faces,
      std::string tenant = "", std::optional<fecheck::FeCheckOptions> fe_check = std::nullopt);
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  // Constant facts; any thread, no lock.
  const std::string& id() const { return id_; }
  const std::string& label() const { return label_; }
  const std::string& tenant() const { return tenant_; }  // "" without tenants
  const SimplifyOptions& options() const { return options_; }
  const std::optional<fecheck::FeCheckOptions>& fe_check() const { return fe_check_; }
  uint64_t input_vertices() const { return input_vertices_; }
  uint64_t input_faces() const { return input_faces_; }
  Clock::time_point created() const { return created_; }
  int contexts() const;  // threads (native) or SPEs (cell)

  // --- The handler ---
  // The upload is complete: the job waits in the queue, holding its input.
  void Enqueue(PreparedMesh input);
  // What changed since the handler last looked.
  struct Update {
    std::vector<PassStats> passes;  // passes after the first `seen`
    JobState state = JobState::kUploading;
    bool done = false;
    bool cancel_requested = false;
  };
  // Waits until passes beyond the first `seen` exist, the job ended, a cancel was requested (when
  // `cancel_seen` is false) or `until` came; returns the new passes and the state.
  Update WaitForChange(size_t seen, bool cancel_seen, Clock::time_point until) const;
  // A finished job's result and output mesh, moved out (once).
  struct Output {
    SimplifyResult result;
    RawMesh mesh;
    double queue_seconds = 0;
    double output_seconds = 0;  // the runner's OutputMesh (part of the encode stage)
    std::optional<fecheck::FeCheckReport> fe_check;  // when the job asked for it
  };
  // The final status of an ended job; when it is OK, *out receives the result and the output.
  grpc::Status TakeOutput(Output* out);
  // The call is over with `status`: ends the job with it when nothing has (CANCELLED and
  // DEADLINE_EXCEEDED as cancelled, any other code as failed; OK cannot end a job) and frees the
  // input and any output left. A succeeded job whose call ends otherwise than OK keeps its state
  // and takes the call's status ("result not delivered: ...").
  void Close(const grpc::Status& status);

  // --- The runner ---
  // A worker takes the job: kRunning, and the input handed over. nullopt when the job ended
  // while it waited (cancelled out of the queue, shutdown).
  std::optional<PreparedMesh> Start();
  void StartRemoval(int pass);          // a pass's removals begin
  void AddPass(const PassStats& pass);  // wakes the handler
  // output_seconds: how long OutputMesh took to make `output`.
  void Succeed(const SimplifyResult& result, RawMesh output, double output_seconds,
               std::optional<fecheck::FeCheckReport> fe_check = std::nullopt);
  // Ends the job; false (and nothing changes) when it had ended already. The input goes.
  bool Finish(JobState final_state, grpc::Status status);
  // Ends the job as cancelled with the status its cancel request gave.
  bool FinishCancelled();
  double queued_seconds() const;  // from Enqueue to Start (or to now)
  double run_seconds() const;     // from Start to the end (or to now)

  // --- Anyone ---
  // The first request wins and sets the job's final status; the engine polls cancelled().
  // Returns the state found; an ended job is left as it is.
  JobState RequestCancel(grpc::StatusCode code, std::string message);
  bool cancelled() const { return cancel_.load(std::memory_order_relaxed); }
  grpc::Status cancel_status() const;  // OK when none was requested
  // Fills the ListJobs/GetJob view.
  void Describe(v1::JobInfo* info, int queue_position) const;

 private:
  bool done() const;  // requires mu_
  bool FinishLocked(JobState final_state, grpc::Status status);
  double QueuedSecondsLocked(Clock::time_point now) const;
  double RunSecondsLocked(Clock::time_point now) const;

  const std::string id_, label_, tenant_;
  const SimplifyOptions options_;
  const uint64_t input_vertices_, input_faces_;
  const std::optional<fecheck::FeCheckOptions> fe_check_;
  const Clock::time_point created_ = Clock::now();
  std::atomic<bool> cancel_{false};

  mutable std::mutex mu_;
  mutable std::condition_variable cv_;  // signalled on every change below
  // Guarded by mu_:
  JobState state_ = JobState::kUploading;
  std::optional<PreparedMesh> input_;  // from Enqueue until Start (or the end)
  std::vector<PassStats> passes_;
  uint32_t passes_started_ = 0;  // passes whose removals began
  std::optional<SimplifyResult> result_;
  RawMesh output_;
  double output_seconds_ = 0;
  std::optional<fecheck::FeCheckReport> fe_check_report_;
  grpc::Status status_;  // final once done()
  grpc::StatusCode cancel_code_ = grpc::StatusCode::OK;
  std::string cancel_message_;
  Clock::time_point queued_at_{}, started_at_{}, finished_at_{};
};

v1::JobState ToProto(JobState s);
const char* StatusCodeName(grpc::StatusCode code);

}  // namespace femsimp::server
