// One simplification job, shared by the RPC handler that streams it and the worker that runs it.
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
#include "engine/simplify.h"
#include "femsimp/v1/femsimp.pb.h"
#include "grpcpp/support/status.h"

namespace femsimp::server {

enum class JobState { kUploading, kQueued, kRunning, kSucceeded, kFailed, kCancelled };

struct Job {
  using Clock = std::chrono::steady_clock;

  Job(std::string id, std::string label, SimplifyOptions options, uint64_t vertices, uint64_t faces,
      bool face_groups);

  const std::string id, label;
  const SimplifyOptions options;
  const uint64_t input_vertices, input_faces;
  const bool has_face_groups;
  const Clock::time_point created = Clock::now();

  // First request wins; the engine polls cancelled() between and inside passes.
  void RequestCancel(grpc::StatusCode code, const std::string& message);
  bool cancelled() const { return cancel_.load(std::memory_order_relaxed); }

  // Marks the job finished with its status and wakes the handler.
  void Finish(JobState final_state, grpc::Status status);
  bool done() const;  // requires mu

  int contexts() const;  // threads (native) or SPEs (cell)

  // Fills the ListJobs/GetJob view; takes mu.
  void Describe(v1::JobInfo* info, int queue_position);

  mutable std::mutex mu;
  std::condition_variable cv;  // signalled on every change below
  // Guarded by mu:
  JobState state = JobState::kUploading;
  std::optional<Mesh> mesh;  // the input until the worker is done with it
  std::vector<PassStats> passes;
  std::optional<SimplifyResult> result;
  RawMesh output;
  grpc::Status status;  // final status once done()
  grpc::StatusCode cancel_code = grpc::StatusCode::OK;
  std::string cancel_message;
  Clock::time_point queued_at{}, started_at{}, finished_at{};

 private:
  std::atomic<bool> cancel_{false};
};

const char* StateName(JobState s);
v1::JobState ToProto(JobState s);
const char* StatusCodeName(grpc::StatusCode code);

}  // namespace femsimp::server
