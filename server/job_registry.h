// Jobs by id for GetJob/CancelJob/ListJobs: every unfinished job and the most recent finished.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "server/job.h"

namespace femsimp::server {

class JobRegistry {
 public:
  explicit JobRegistry(size_t finished_kept);

  // 128 random bits in hex: unguessable, so a job id is as good as a capability to it.
  std::string NewId();
  void Add(std::shared_ptr<Job> job);
  // Adds the job unless its tenant already has `max_per_tenant` unfinished jobs (0: no limit).
  bool AddWithin(std::shared_ptr<Job> job, size_t max_per_tenant);
  // Moves the job to the finished list (dropping the oldest beyond the limit).
  void MarkFinished(const std::shared_ptr<Job>& job);
  std::shared_ptr<Job> Find(const std::string& id) const;
  // Newest first.
  std::vector<std::shared_ptr<Job>> List(bool include_finished) const;
  std::vector<std::shared_ptr<Job>> Unfinished() const;

 private:
  const size_t finished_kept_;
  mutable std::mutex mu_;
  std::random_device random_;  // guarded by mu_
  std::map<std::string, std::shared_ptr<Job>> active_;
  std::deque<std::shared_ptr<Job>> finished_;
};

}  // namespace femsimp::server
