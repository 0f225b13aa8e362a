// The thread pool hands an exception thrown in any context (std::bad_alloc, in practice) back to
// its caller once every context is done, and stays usable; the work shares over its contexts hand
// out every item once.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <new>
#include <thread>
#include <vector>

#include "engine/work_shares.h"
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

// Every item goes to exactly one context, whatever the timing; a context alone takes its own share
// front to back, then the others' from their backs, and chunks shrink as a share runs out.
TEST(WorkShares, EveryItemOnceAndOwnShareFirst) {
  WorkShares alone(3);
  alone.Reset(30);
  std::vector<std::pair<size_t, size_t>> chunks;
  size_t begin, end;
  while (alone.Next(1, 4, &begin, &end)) chunks.emplace_back(begin, end);
  ASSERT_FALSE(chunks.empty());
  EXPECT_EQ(chunks.front(), std::make_pair(size_t{10}, size_t{12}));  // a quarter of 10, from 10
  std::vector<int> taken(30, 0);
  for (auto [b, e] : chunks) {
    EXPECT_LT(b, e);
    EXPECT_LE(e - b, 4u);
    for (size_t i = b; i < e; ++i) ++taken[i];
  }
  for (size_t i = 0; i < 30; ++i) EXPECT_EQ(taken[i], 1) << i;
  // Its own share [10, 20) first, front to back, then context 2's and 0's from their backs.
  size_t k = 0;
  for (size_t next = 10; next < 20; next = chunks[k++].second) ASSERT_EQ(chunks[k].first, next);
  EXPECT_EQ(chunks[k].second, 30u);
  EXPECT_EQ(chunks.back().first, 0u);

  WorkerPool pool(4);
  WorkShares shares(pool.size());
  for (size_t count : {0, 1, 3, 1000, 100003}) {
    std::vector<std::atomic<int>> hits(count);
    shares.Reset(count);
    pool.Run([&](int c) {
      size_t b, e;
      while (shares.Next(c, 64, &b, &e))
        for (size_t i = b; i < e; ++i) hits[i].fetch_add(1, std::memory_order_relaxed);
    });
    for (size_t i = 0; i < count; ++i)
      ASSERT_EQ(hits[i].load(), 1) << count << " items, item " << i;
  }
}

}  // namespace
}  // namespace femsimp
