// Workers that take jobs from the queue and run the engine on them, one job per worker.
#pragma once

#include <atomic>
#include <functional>
#include <thread>
#include <vector>

#include "server/job_queue.h"
#include "server/job_registry.h"
#include "server/metrics.h"

namespace femsimp::server {

class WorkerPool {
 public:
  WorkerPool(int workers, JobQueue& queue, JobRegistry& registry, Metrics& metrics);
  ~WorkerPool();
  // Returns once the queue is closed and every running job has finished.
  void Join();
  int running() const { return running_.load(); }

 private:
  void Loop();
  void Run(const std::shared_ptr<Job>& job);

  JobQueue& queue_;
  JobRegistry& registry_;
  Metrics& metrics_;
  std::atomic<int> running_{0};
  std::vector<std::thread> threads_;
};

}  // namespace femsimp::server
