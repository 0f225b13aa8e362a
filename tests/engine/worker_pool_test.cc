// The thread pool hands an exception thrown in any context (std::bad_alloc, in practice) back to
// its caller once every context is done, and stays usable.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <new>
#include <thread>
#include <vector>

#include "engine/worker_pool.h"

namespace femsimp {
namespace {

TEST(WorkerPool, AnExceptionInAnyContextReachesTheCallerAfterAllAreDone) {
  WorkerPool pool(4);
  for (int thrower = 0; thrower < pool.size(); ++thrower) {
    std::atomic<int> finished{0};
    EXPECT_THROW(pool.Run([&](int c) {
      if (c == thrower) throw std::bad_alloc();
      finished.fetch_add(1);
    }),
                 std::bad_alloc)
        << "context " << thrower;
    EXPECT_EQ(finished.load(), pool.size() - 1);  // the others ran to their end
  }
  std::atomic<int> ran{0};
  pool.Run([&](int) { ran.fetch_add(1); });
  EXPECT_EQ(ran.load(), pool.size());
}

// The rounds call Run thousands of times with short gaps (the idle contexts spin through them)
// and long ones (they sleep): every call runs every context once, sees what the caller wrote
// before it, and hands back what the contexts wrote.
TEST(WorkerPool, ShortAndLongGapsBetweenRunsLoseNoContextAndNoWrite) {
  WorkerPool pool(3);
  std::vector<int> cells(pool.size(), 0);
  int input = 0;
  for (int round = 1; round <= 3000; ++round) {
    input = round;  // plain writes: the pool orders them
    pool.Run([&](int c) { cells[c] += input; });
    for (int c = 0; c < pool.size(); ++c) ASSERT_EQ(cells[c], round * (round + 1) / 2) << round;
    if (round % 1000 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// A pool destroyed while its contexts spin or sleep stops them.
TEST(WorkerPool, StopsWhetherItsContextsSpinOrSleep) {
  for (int wait_ms : {0, 20}) {
    WorkerPool pool(4);
    std::atomic<int> ran{0};
    pool.Run([&](int) { ran.fetch_add(1); });
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    EXPECT_EQ(ran.load(), 4);
  }
}

}  // namespace
}  // namespace femsimp
