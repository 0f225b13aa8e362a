#include "server/job_queue.h"

#include <algorithm>

namespace femsimp::server {

bool JobQueue::TryReserve() {
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_ || jobs_.size() + reserved_ >= capacity_) return false;
  ++reserved_;
  return true;
}

void JobQueue::CancelReservation() {
  std::lock_guard<std::mutex> lock(mu_);
  if (reserved_ > 0) --reserved_;
}

bool JobQueue::PushReserved(std::shared_ptr<Job> job) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (reserved_ > 0) --reserved_;
    if (closed_) return false;
    jobs_.push_back(std::move(job));
  }
  cv_.notify_one();
  return true;
}

std::shared_ptr<Job> JobQueue::Pop() {
  std::unique_lock<std::mutex> lock(mu_);
  cv_.wait(lock, [&] { return closed_ || !jobs_.empty(); });
  if (closed_ || jobs_.empty()) return nullptr;
  std::shared_ptr<Job> job = std::move(jobs_.front());
  jobs_.pop_front();
  return job;
}

bool JobQueue::Remove(const Job* job) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = std::find_if(jobs_.begin(), jobs_.end(), [&](const auto& j) { return j.get() == job; });
  if (it == jobs_.end()) return false;
  jobs_.erase(it);
  return true;
}

int JobQueue::Position(const Job* job) const {
  std::lock_guard<std::mutex> lock(mu_);
  for (size_t i = 0; i < jobs_.size(); ++i)
    if (jobs_[i].get() == job) return static_cast<int>(i);
  return -1;
}

void JobQueue::Close() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

std::vector<std::shared_ptr<Job>> JobQueue::TakeAll() {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<std::shared_ptr<Job>> out(jobs_.begin(), jobs_.end());
  jobs_.clear();
  return out;
}

size_t JobQueue::waiting() const {
  std::lock_guard<std::mutex> lock(mu_);
  return jobs_.size();
}

}  // namespace femsimp::server
