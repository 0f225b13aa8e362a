#include "engine/worker_pool.h"

namespace femsimp {
namespace {

// True once done() holds, polling it for at most `limit`.
template <class Done>
bool SpinUntil(Done done, std::chrono::microseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  for (int i = 1;; ++i) {
    if (done()) return true;
    if (i % 64 == 0 && std::chrono::steady_clock::now() >= until) return false;
    SpinPause();
  }
}

}  // namespace

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
    pending_.store(contexts_ - 1, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
  }
  start_cv_.notify_all();
  // The other contexts use fn until they are done: wait for them even if it throws here.
  std::exception_ptr failure;
  try {
    fn(0);
  } catch (...) {
    failure = std::current_exception();
  }
  SpinUntil([this] { return pending_.load(std::memory_order_acquire) == 0; }, kSpin);
  std::unique_lock<std::mutex> lock(mu_);
  done_cv_.wait(lock, [this] { return pending_.load(std::memory_order_acquire) == 0; });
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
    const auto started = [&] { return generation_.load(std::memory_order_acquire) != seen; };
    SpinUntil(started, kSpin);  // then the wait below returns at once, or sleeps
    {
      std::unique_lock<std::mutex> lock(mu_);
      start_cv_.wait(lock, [&] { return quit_ || started(); });
      if (quit_) return;
      seen = generation_.load(std::memory_order_acquire);
      job = job_;
    }
    std::exception_ptr failure;
    try {
      (*job)(context);
    } catch (...) {
      failure = std::current_exception();
    }
    if (failure) {
      std::lock_guard<std::mutex> lock(mu_);
      if (!failure_) failure_ = failure;
    }
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      // The caller checks pending_ under the lock: taking it here loses no wake-up.
      std::lock_guard<std::mutex> lock(mu_);
      done_cv_.notify_one();
    }
  }
}

}  // namespace femsimp
