#include "server/job_registry.h"

#include <algorithm>
#include <random>

#include "absl/strings/str_format.h"

namespace femsimp::server {

JobRegistry::JobRegistry(size_t finished_kept) : finished_kept_(finished_kept) {}

std::string JobRegistry::NewId() {
  std::lock_guard<std::mutex> lock(mu_);
  for (;;) {
    std::string id;
    for (int i = 0; i < 4; ++i) absl::StrAppendFormat(&id, "%08x", random_());
    if (active_.count(id) == 0) return id;  // 2^-128 per pair: never, but cheap to be sure
  }
}

void JobRegistry::Add(std::shared_ptr<Job> job) { AddWithin(std::move(job), 0); }

bool JobRegistry::AddWithin(std::shared_ptr<Job> job, size_t max_per_tenant) {
  std::lock_guard<std::mutex> lock(mu_);
  if (max_per_tenant > 0) {
    size_t mine = 0;
    for (const auto& [id, other] : active_) mine += other->tenant() == job->tenant();
    if (mine >= max_per_tenant) return false;
  }
  active_[job->id()] = std::move(job);
  return true;
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
