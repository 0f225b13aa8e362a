#include "server/worker_pool.h"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "proto/wire.h"
#include "server/log.h"
#include "server/status_util.h"

namespace femsimp::server {
namespace {

double Seconds(Job::Clock::time_point a, Job::Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

WorkerPool::WorkerPool(int workers, JobQueue& queue, JobRegistry& registry, Metrics& metrics)
    : queue_(queue), registry_(registry), metrics_(metrics) {
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { Loop(); });
}

WorkerPool::~WorkerPool() {
  queue_.Close();
  Join();
}

void WorkerPool::Join() {
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
}

void WorkerPool::Loop() {
  while (std::shared_ptr<Job> job = queue_.Pop()) {
    metrics_.SetQueueDepth(queue_.waiting());
    Run(job);
  }
}

void WorkerPool::Run(const std::shared_ptr<Job>& job) {
  std::optional<Mesh> mesh;
  double queued;
  {
    std::lock_guard<std::mutex> lock(job->mu);
    if (job->done()) return;  // finished while queued (shutdown)
    mesh = std::move(job->mesh);
    job->mesh.reset();
    job->state = JobState::kRunning;
    job->started_at = Job::Clock::now();
    queued = Seconds(job->queued_at, job->started_at);
  }
  job->cv.notify_all();
  if (job->cancelled() || !mesh) {  // cancelled between Pop and here
    grpc::Status s;
    {
      std::lock_guard<std::mutex> lock(job->mu);
      s = grpc::Status(job->cancel_code, job->cancel_message);
    }
    job->Finish(JobState::kCancelled, s);
    registry_.MarkFinished(job);
    return;
  }

  metrics_.SetRunning(++running_);
  const SimplifyOptions& o = job->options;
  LogLine(absl::StrFormat(
      "job %s start: label=\"%s\" vertices=%u faces=%u fields=%u backend=%s contexts=%d "
      "ratio=%g target_vertices=%u cost=%s tolerance=%g tolerance_relative=%g queued=%.3fs",
      job->id, job->label, job->input_vertices, job->input_faces, mesh->field_names().size(),
      wire::BackendName(o.backend), job->contexts(), o.ratio, o.target_vertices,
      CostKindName(o.cost), o.tolerance, o.tolerance_relative, queued));

  SimplifyControl control;
  control.cancelled = [&job] { return job->cancelled(); };
  control.on_pass = [&](const PassStats& p) {
    metrics_.PassFinished(o.backend, p);
    {
      std::lock_guard<std::mutex> lock(job->mu);
      job->passes.push_back(p);
    }
    job->cv.notify_all();
  };
  absl::StatusOr<SimplifyResult> result = Simplify(*mesh, o, control);

  JobState final_state;
  grpc::Status status;
  if (!result.ok()) {
    final_state = JobState::kFailed;
    status = ToGrpc(absl::Status(result.status().code(), absl::StrCat("simplification failed: ",
                                                                      result.status().message())));
  } else if (job->cancelled()) {
    final_state = JobState::kCancelled;
    std::lock_guard<std::mutex> lock(job->mu);
    status = grpc::Status(job->cancel_code, job->cancel_message);
  } else {
    final_state = JobState::kSucceeded;
    RawMesh out = mesh->ToRaw();
    std::lock_guard<std::mutex> lock(job->mu);
    job->output = std::move(out);
    job->result = *result;
  }
  mesh.reset();  // the engine's arrays go before the next job starts
  // Metrics before Finish(): a client that saw its job end then sees it counted.
  if (final_state == JobState::kSucceeded)
    metrics_.JobCompleted(o.backend, job->contexts(), result->engine_seconds, queued, *result);
  metrics_.SetRunning(--running_);
  job->Finish(final_state, status);
  registry_.MarkFinished(job);

  double run_seconds;
  {
    std::lock_guard<std::mutex> lock(job->mu);
    run_seconds = Seconds(job->started_at, job->finished_at);
  }
  if (final_state == JobState::kSucceeded) {
    double speedup = result->engine_seconds > 0 ? result->busy_seconds / result->engine_seconds : 0;
    LogLine(absl::StrFormat(
        "job %s end: OK vertices=%u->%u faces=%u->%u passes=%u engine=%.3fs busy=%.3fs "
        "speedup=%.2f stop=%s run=%.3fs",
        job->id, result->input_vertices, result->output_vertices, result->input_faces,
        result->output_faces, result->passes.size(), result->engine_seconds, result->busy_seconds,
        speedup, StopReasonName(result->stop_reason), run_seconds));
  } else {
    LogLine(absl::StrFormat("job %s end: %s \"%s\" passes=%u run=%.3fs", job->id,
                            StatusCodeName(status.error_code()), status.error_message(),
                            result.ok() ? result->passes.size() : 0, run_seconds));
  }
}

}  // namespace femsimp::server
