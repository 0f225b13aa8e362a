#include "server/job_registry.h"

#include <algorithm>
#include <random>

#include "absl/strings/str_format.h"

namespace femsimp::server {

JobRegistry::JobRegistry(size_t finished_kept)
    : finished_kept_(finished_kept), salt_(std::random_device{}() & 0xffffff) {}

std::string JobRegistry::NewId() {
  std::lock_guard<std::mutex> lock(mu_);
  return absl::StrFormat("%06x-%d", salt_, next_++);
}

void JobRegistry::Add(std::shared_ptr<Job> job) {
  std::lock_guard<std::mutex> lock(mu_);
  active_[job->id()] = std::move(job);
}

void JobRegistry::MarkFinished(const std::shared_ptr<Job>& job) {
  std::lock_guard<std::mutex> lock(mu_);
  if (active_.erase(job->id()) == 0) return;
  finished_.push_front(job);
  while (finished_.size() > finished_kept_) finished_.pop_back();
}

std::shared_ptr<Job> JobRegistry::Find(const std::string& id) const {
  std::lock_guard<std::mutex> lock(mu_);
  if (auto it = active_.find(id); it != active_.end()) return it->second;
  for (const auto& j : finished_)
    if (j->id() == id) return j;
  return nullptr;
}

std::vector<std::shared_ptr<Job>> JobRegistry::List(bool include_finished) const {
  std::vector<std::shared_ptr<Job>> out = Unfinished();
  std::lock_guard<std::mutex> lock(mu_);
  if (include_finished) out.insert(out.end(), finished_.begin(), finished_.end());
  return out;
}

std::vector<std::shared_ptr<Job>> JobRegistry::Unfinished() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<std::shared_ptr<Job>> out;
  for (const auto& [id, j] : active_) out.push_back(j);
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a->created() > b->created(); });
  return out;
}

}  // namespace femsimp::server
