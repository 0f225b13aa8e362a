// Runs the queued jobs: each context of one femsimp::WorkerPool (the codebase's one thread pool)
// takes the next job from the queue and runs the engine on it, one job at a time, until the
// queue is closed. Context 0 is the runner's own thread (the pool's caller), the others the
// pool's threads.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include "absl/status/statusor.h"
#include "engine/worker_pool.h"
#include "fecheck/fe_check.h"
#include "server/job_queue.h"
#include "server/job_registry.h"
#include "server/metrics.h"

namespace femsimp::server {

class JobRunner {
 public:
  JobRunner(int workers, JobQueue& queue, JobRegistry& registry, Metrics& metrics);
  ~JobRunner();  // closes the queue and joins
  JobRunner(const JobRunner&) = delete;
  JobRunner& operator=(const JobRunner&) = delete;

  // Returns once the queue is closed and every running job has finished.
  void Join();
  int running() const { return running_.load(); }

 private:
  void Work();  // one context: jobs until the queue is closed
  void Run(const std::shared_ptr<Job>& job);
  // The job's FE check of its (repaired) input against its output; errors prefixed "FE check: ".
  static absl::StatusOr<fecheck::FeCheckReport> RunFeCheck(const Job& job,
                                                           const std::optional<RawMesh>& input,
                                                           const RawMesh& output);

  JobQueue& queue_;
  JobRegistry& registry_;
  Metrics& metrics_;
  std::atomic<int> running_{0};
  WorkerPool pool_;
  std::thread driver_;  // calls pool_.Run(Work), i.e. is context 0
};

}  // namespace femsimp::server
