// The thread pool hands an exception thrown in any context (std::bad_alloc, in practice) back to
// its caller once every context is done, and stays usable.
#include <gtest/gtest.h>

#include <atomic>
#include <new>

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

}  // namespace
}  // namespace femsimp
