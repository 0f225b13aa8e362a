#include "cellsim/soft_threads.h"

#include <cstring>
#include <numeric>
#include <vector>

#include "cellsim/spe_context.h"
#include "gtest/gtest.h"
#include "tests/support/cellsim.h"

namespace femsimp::cellsim {
namespace {

using testing::MakeSpe;
using testing::Quad;
using testing::QuadArray;

class SoftThreadsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(memory_.Register(data_.data(), data_.bytes(), "data").ok());
    // One item per line, so that every first read of an item misses.
    for (uint32_t i = 0; i < 64; ++i) items_.push_back(8 * i);
  }

  // Reads the quad of each work item through the cache and does some compute per item;
  // returns the sum of the first words read.
  uint64_t Process(SpeContext& spe, int k) {
    WorkPlan plan = WorkPlan::PerSpe({items_});
    spe.BeginRun(&plan, nullptr, nullptr);
    uint64_t sum = 0;
    absl::Status s = spe.RunThreads(k, [&](SpeContext& ctx, int) {
      while (std::optional<uint64_t> item = ctx.NextWorkItem()) {
        absl::StatusOr<Quad> q = ctx.cache().ReadValue<Quad>(Ea(&data_[*item]));
        if (!q.ok()) return ctx.ReportError(q.status());
        ctx.AddComputeCycles(300);
        sum += q->w[0];
      }
    });
    spe.EndRun();
    EXPECT_TRUE(s.ok()) << s;
    EXPECT_TRUE(spe.error().ok()) << spe.error();
    return sum;
  }

  QuadArray data_{1024};
  MainMemory memory_;
  std::vector<uint32_t> items_;
};

TEST_F(SoftThreadsTest, OneThreadCompletesAllWorkWithoutSwitching) {
  auto spe = MakeSpe(memory_);
  const uint64_t expected = std::accumulate(items_.begin(), items_.end(), uint64_t{0});
  EXPECT_EQ(Process(*spe, 1), expected);
  EXPECT_EQ(spe->counters().work_items, items_.size());
  EXPECT_EQ(spe->counters().cache_misses, items_.size());
  EXPECT_EQ(spe->counters().thread_switches, 0u);
}

TEST_F(SoftThreadsTest, SeveralThreadsCompleteAllWorkAndHideLatency) {
  auto one = MakeSpe(memory_);
  auto four = MakeSpe(memory_);
  const uint64_t expected = std::accumulate(items_.begin(), items_.end(), uint64_t{0});
  EXPECT_EQ(Process(*one, 1), expected);
  EXPECT_EQ(Process(*four, 4), expected);
  const SpeCounters& c1 = one->counters();
  const SpeCounters& c4 = four->counters();
  EXPECT_EQ(c4.work_items, items_.size());
  EXPECT_EQ(c4.cache_misses, items_.size());
  EXPECT_GT(c4.thread_switches, 0u);
  EXPECT_LE(c4.thread_switches, c4.cache_misses);  // Only misses switch.
  EXPECT_EQ(c4.switch_cycles, c4.thread_switches * four->config().cost.thread_switch_cycles);
  // The same compute, but the other threads' work overlaps the transfers.
  EXPECT_EQ(c4.compute_cycles, c1.compute_cycles);
  EXPECT_LT(c4.dma_stall_cycles, c1.dma_stall_cycles / 2);
  EXPECT_LT(four->Now(), one->Now());
  EXPECT_EQ(c4.ModeledCycles(), four->Now());
}

TEST_F(SoftThreadsTest, NoSwitchesWhenEverythingHits) {
  auto spe = MakeSpe(memory_);
  Process(*spe, 1);  // Warms the cache: 64 lines fit in 64 KiB.
  spe->counters().Reset();
  Process(*spe, 4);
  EXPECT_EQ(spe->counters().cache_misses, 0u);
  EXPECT_EQ(spe->counters().cache_hits, items_.size());
  EXPECT_EQ(spe->counters().thread_switches, 0u);
}

TEST_F(SoftThreadsTest, TouchReportAndYieldSwitchOnlyOnRealMisses) {
  auto spe = MakeSpe(memory_);
  ASSERT_TRUE(spe->cache().ReadValue<Quad>(Ea(&data_[0])).ok());  // Line 0 present.
  std::vector<int> order;
  absl::Status s = spe->RunThreads(2, [&](SpeContext& ctx, int t) {
    const uint64_t ea = Ea(&data_[t == 0 ? 0 : 64]);
    absl::StatusOr<bool> present = ctx.cache().TouchReport(ea);
    if (!present.ok()) return ctx.ReportError(present.status());
    if (!*present) ctx.Yield();
    order.push_back(t);
  });
  ASSERT_TRUE(s.ok()) << s;
  // Thread 0 hit and ran to the end; thread 1 missed and yielded, but nobody else was ready.
  EXPECT_EQ(order, (std::vector<int>{0, 1}));
  EXPECT_EQ(spe->counters().thread_switches, 0u);

  order.clear();
  spe->cache().InvalidateAll();
  ASSERT_TRUE(spe->cache().ReadValue<Quad>(Ea(&data_[0])).ok());
  s = spe->RunThreads(2, [&](SpeContext& ctx, int t) {
    // Thread 0 misses, thread 1 hits.
    absl::StatusOr<bool> present = ctx.cache().TouchReport(Ea(&data_[t == 0 ? 128 : 0]));
    if (!present.ok()) return ctx.ReportError(present.status());
    if (!*present) ctx.Yield();
    order.push_back(t);
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(order, (std::vector<int>{1, 0}));  // Thread 0 yielded to thread 1.
  EXPECT_EQ(spe->counters().thread_switches, 1u);
}

// Two registered regions can share a cache line (two small arrays next to each other on the
// heap: the engine's test meshes have them). Two software threads reading one part each must
// both finish: each part's fill used to take over the way of the other part, so the two
// threads refetched the line in turn forever (a determinism test hung in CI that way).
TEST(SoftThreadsSharedLine, TwoRegionsInOneLineAreBothRead) {
  QuadArray data(64);  // line-aligned: quads 0..7 are one 128-byte line
  MainMemory memory;
  ASSERT_TRUE(memory.Register(&data[0], 3 * sizeof(Quad), "a").ok());
  ASSERT_TRUE(memory.Register(&data[4], 60 * sizeof(Quad), "b").ok());
  auto spe = MakeSpe(memory);
  uint32_t seen[2] = {0, 0};
  absl::Status s = spe->RunThreads(2, [&](SpeContext& ctx, int t) {
    for (int i = 0; i < 20; ++i) {
      absl::StatusOr<Quad> q = ctx.cache().ReadValue<Quad>(Ea(&data[t == 0 ? 1 : 5]));
      if (!q.ok()) return ctx.ReportError(q.status());
      seen[t] = q->w[0];
      ctx.AddComputeCycles(50);
    }
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_TRUE(spe->error().ok()) << spe->error();
  EXPECT_EQ(seen[0], 1u);
  EXPECT_EQ(seen[1], 5u);
  // Both parts are fetched once and then held in two ways.
  EXPECT_EQ(spe->counters().cache_misses, 2u);
}

TEST_F(SoftThreadsTest, StacksLiveInTheLocalStoreAndRunsDoNotNest) {
  auto spe = MakeSpe(memory_);
  absl::Status inner;
  absl::Status s = spe->RunThreads(2, [&](SpeContext& ctx, int t) {
    // A stack buffer is a local-store buffer: DMA accepts it.
    alignas(16) Quad q{{static_cast<uint32_t>(1000 + t), 0, 0, 0}};
    EXPECT_TRUE(ctx.local_store().Contains(&q, sizeof(q)));
    EXPECT_TRUE(ctx.dma().Put(&q, Ea(&data_[500 + t]), 16, 0).ok());
    (void)ctx.dma().WaitTagMask(1);
    EXPECT_EQ(ctx.thread_index(), t);
    EXPECT_EQ(ctx.num_threads(), 2);
    if (t == 0) inner = ctx.RunThreads(1, [](SpeContext&, int) {});
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(inner.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(data_[500].w[0], 1000u);
  EXPECT_EQ(data_[501].w[0], 1001u);
  EXPECT_EQ(spe->thread_index(), 0);
  EXPECT_EQ(spe->RunThreads(0, [](SpeContext&, int) {}).code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace femsimp::cellsim
