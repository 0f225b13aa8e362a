// femsimp's one thread pool: a fixed set of contexts that Run one function each and return when
// all are done; the caller is context 0. The engine runs a function per pass phase on it (the
// progress callback stays on the caller's thread; every context polls cancellation); the server's
// JobRunner runs a job loop on each context for the server's lifetime. The deterministic rounds
// call Run thousands of times a pass with short serial steps between: an idle context and the
// caller spin briefly (kSpin) before they sleep, so that a round's phase does not wait for a
// thread to be woken (a futex wake-up per phase was a tenth of a 2-thread run).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace femsimp {

// A spinning context's pause between polls (lets the core's other thread run).
inline void SpinPause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

class WorkerPool {
 public:
  explicit WorkerPool(int contexts);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return contexts_; }
  // Runs fn(context) on every context and returns when all are done. An exception thrown in a
  // context (std::bad_alloc: the engine reports errors as statuses) is rethrown here once every
  // context has finished, the caller's own first; the pool stays usable.
  void Run(const std::function<void(int)>& fn);

 private:
  void Loop(int context);

  static constexpr std::chrono::microseconds kSpin{50};

  const int contexts_;
  std::vector<std::thread> threads_;
  std::mutex mu_;
  std::condition_variable start_cv_, done_cv_;
  const std::function<void(int)>* job_ = nullptr;  // guarded by mu_
  // Also read without the lock, by the spinning contexts and caller.
  std::atomic<uint64_t> generation_{0};
  std::atomic<int> pending_{0};
  std::exception_ptr failure_;  // the first exception of a context other than the caller
  bool quit_ = false;
};

// Runs body(begin, end) over [0, count) in chunks of `chunk` items that the pool's contexts take
// in turn (on the caller alone without a pool, with one context, or for a single chunk); each
// chunk polls `cancelled` (may be empty) first, and once it says true the rest is left undone and
// the call returns false.
template <class Body>
bool RunChunked(WorkerPool* pool, uint32_t count, uint32_t chunk,
                const std::function<bool()>& cancelled, const Body& body) {
  std::atomic<uint32_t> next{0};
  std::atomic<bool> stopped{false};
  const auto work = [&](int) {
    for (;;) {
      const uint32_t begin = next.fetch_add(chunk, std::memory_order_relaxed);
      if (begin >= count || stopped.load(std::memory_order_relaxed)) return;
      if (cancelled && cancelled()) {
        stopped.store(true, std::memory_order_relaxed);
        return;
      }
      body(begin, count - begin < chunk ? count : begin + chunk);
    }
  };
  if (pool == nullptr || pool->size() == 1 || count <= chunk)
    work(0);
  else
    pool->Run(work);
  return !stopped.load();
}

}  // namespace femsimp
