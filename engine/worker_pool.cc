#include "engine/worker_pool.h"

namespace femsimp {

WorkerPool::WorkerPool(int contexts) : contexts_(contexts) {
  for (int c = 1; c < contexts_; ++c) threads_.emplace_back([this, c] { Loop(c); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    quit_ = true;
  }
  start_cv_.notify_all();
  for (auto& t : threads_) t.join();
}

void WorkerPool::Run(const std::function<void(int)>& fn) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    job_ = &fn;
    pending_ = contexts_ - 1;
    ++generation_;
  }
  start_cv_.notify_all();
  // The other contexts use fn until they are done: wait for them even if it throws here.
  std::exception_ptr failure;
  try {
    fn(0);
  } catch (...) {
    failure = std::current_exception();
  }
  std::unique_lock<std::mutex> lock(mu_);
  done_cv_.wait(lock, [this] { return pending_ == 0; });
  job_ = nullptr;
  if (!failure) failure = failure_;
  failure_ = nullptr;
  lock.unlock();
  if (failure) std::rethrow_exception(failure);
}

void WorkerPool::Loop(int context) {
  uint64_t seen = 0;
  for (;;) {
    const std::function<void(int)>* job;
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
      job = job_;
    }
    std::exception_ptr failure;
    try {
      (*job)(context);
    } catch (...) {
      failure = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (failure && !failure_) failure_ = failure;
      if (--pending_ == 0) done_cv_.notify_one();
    }
  }
}

}  // namespace femsimp
