#include "cellsim/software_cache.h"

#include <cstring>
#include <vector>

#include "cellsim/spe_context.h"
#include "gtest/gtest.h"
#include "tests/support/cellsim.h"

namespace femsimp::cellsim {
namespace {

using testing::MakeSpe;
using testing::Quad;
using testing::QuadArray;

class SoftwareCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = QuadArray(1024);
    ASSERT_TRUE(memory_.Register(data_.data(), data_.bytes(), "data").ok());
  }
  uint64_t EaOf(size_t quad) { return Ea(&data_[quad]); }
  static uint32_t FirstWord(SpeContext& spe, uint64_t ea) {
    absl::StatusOr<Quad> q = spe.cache().ReadValue<Quad>(ea);
    EXPECT_TRUE(q.ok()) << q.status();
    return q.ok() ? q->w[0] : ~0u;
  }
  // Writes word 0 of quad `i` through `spe`'s DMA put, as the engine writes.
  static void PutWord(SpeContext& spe, uint64_t ea, uint32_t value) {
    absl::StatusOr<std::byte*> buf = spe.local_store().Allocate(16);
    ASSERT_TRUE(buf.ok());
    Quad q{{value, 0, 0, 0}};
    std::memcpy(*buf, &q, 16);
    ASSERT_TRUE(spe.dma().Put(*buf, ea, 16, 0).ok());
  }

  QuadArray data_{0};
  MainMemory memory_;
};

TEST_F(SoftwareCacheTest, CountsHitsAndMissesPerLine) {
  auto spe = MakeSpe(memory_);
  // 64 sequential quadwords = 8 lines of 128 bytes: one miss and seven hits per line.
  for (size_t i = 0; i < 64; ++i) EXPECT_EQ(FirstWord(*spe, EaOf(i)), i);
  const SpeCounters& c = spe->counters();
  EXPECT_EQ(c.cache_reads, 64u);
  EXPECT_EQ(c.cache_misses, 8u);
  EXPECT_EQ(c.cache_hits, 56u);
  EXPECT_DOUBLE_EQ(c.HitRatio(), 56.0 / 64.0);
  EXPECT_EQ(c.dma_gets, 8u);
  EXPECT_EQ(c.dma_get_bytes, 8u * 128);
  // Each miss stalled for one line transfer.
  const CostModel& cost = spe->config().cost;
  EXPECT_EQ(c.dma_stall_cycles, 8 * (cost.dma_latency_cycles + 128 / cost.dma_bytes_per_cycle));
  EXPECT_EQ(c.ModeledCycles(), spe->Now());
}

TEST_F(SoftwareCacheTest, LinesStayStaleUntilDirtied) {
  auto reader = MakeSpe(memory_, {}, 0, 2);
  auto writer = MakeSpe(memory_, {}, 1, 2);
  EXPECT_EQ(FirstWord(*reader, EaOf(5)), 5u);
  PutWord(*writer, EaOf(5), 5000);
  EXPECT_EQ(data_[5].w[0], 5000u);             // Main memory has the new value...
  EXPECT_EQ(FirstWord(*reader, EaOf(5)), 5u);  // ...the reader's line does not.
  EXPECT_EQ(FirstWord(*reader, EaOf(6)), 6u);  // Same line, still a hit.
  EXPECT_EQ(reader->counters().cache_misses, 1u);
  reader->cache().Dirty(EaOf(5));
  EXPECT_EQ(reader->counters().cache_dirtied, 1u);
  EXPECT_EQ(FirstWord(*reader, EaOf(5)), 5000u);  // Refetched.
  EXPECT_EQ(reader->counters().cache_misses, 2u);
}

TEST_F(SoftwareCacheTest, OwnPutsAreWrittenThroughUnlessDisabled) {
  auto spe = MakeSpe(memory_);
  EXPECT_EQ(FirstWord(*spe, EaOf(20)), 20u);
  PutWord(*spe, EaOf(20), 2020);
  EXPECT_EQ(FirstWord(*spe, EaOf(20)), 2020u);
  EXPECT_EQ(spe->counters().cache_write_through, 1u);
  EXPECT_EQ(spe->counters().cache_misses, 1u);

  SpeConfig config;
  config.cache.write_through_own_puts = false;
  auto plain = MakeSpe(memory_, config);
  EXPECT_EQ(FirstWord(*plain, EaOf(40)), 40u);
  PutWord(*plain, EaOf(40), 4040);
  EXPECT_EQ(FirstWord(*plain, EaOf(40)), 40u);  // Reads back its own stale line.
  EXPECT_EQ(data_[40].w[0], 4040u);
}

TEST_F(SoftwareCacheTest, InvalidateAllAndFlush) {
  auto spe = MakeSpe(memory_);
  for (size_t i = 0; i < 32; i += 8) FirstWord(*spe, EaOf(i));  // 4 lines.
  data_[0].w[0] = 99;  // Direct write: nothing runs concurrently here.
  spe->cache().InvalidateAll();
  EXPECT_EQ(spe->counters().cache_dirtied, 4u);
  EXPECT_FALSE(spe->cache().Contains(EaOf(8)));
  EXPECT_EQ(FirstWord(*spe, EaOf(0)), 99u);
  EXPECT_EQ(spe->counters().cache_misses, 5u);

  // Flush waits for fills in flight before dropping the lines.
  ASSERT_TRUE(spe->cache().Touch(EaOf(64)).ok());
  EXPECT_TRUE(spe->cache().Contains(EaOf(64)));
  const uint64_t ready = spe->dma().TagCompletionCycle(spe->config().cache.fill_tag);
  EXPECT_LT(spe->Now(), ready);
  spe->cache().Flush();
  EXPECT_EQ(spe->Now(), ready);
  EXPECT_FALSE(spe->cache().Contains(EaOf(64)));
  EXPECT_FALSE(spe->cache().Contains(EaOf(0)));
}

TEST_F(SoftwareCacheTest, LeastRecentlyUsedWayIsEvicted) {
  SpeConfig config;
  config.cache.size_bytes = 4 * 128;  // One set of four ways.
  config.cache.ways = 4;
  auto spe = MakeSpe(memory_, config);
  auto line = [&](int l) { return EaOf(8 * l); };
  for (int l = 0; l < 4; ++l) FirstWord(*spe, line(l));
  FirstWord(*spe, line(0));  // Line 1 is now the LRU.
  FirstWord(*spe, line(4));
  EXPECT_EQ(spe->counters().cache_evictions, 1u);
  EXPECT_TRUE(spe->cache().Contains(line(0)));
  EXPECT_FALSE(spe->cache().Contains(line(1)));
  EXPECT_EQ(spe->counters().cache_misses, 5u);
  EXPECT_EQ(spe->counters().cache_hits, 1u);
}

TEST_F(SoftwareCacheTest, TouchReportSaysWhetherTheDataIsThere) {
  auto spe = MakeSpe(memory_);
  absl::StatusOr<bool> present = spe->cache().TouchReport(EaOf(100));
  ASSERT_TRUE(present.ok());
  EXPECT_FALSE(*present);  // Fill started.
  EXPECT_EQ(spe->counters().cache_prefetches, 1u);
  EXPECT_FALSE(*spe->cache().TouchReport(EaOf(101)));  // In flight: still not usable.
  EXPECT_EQ(spe->counters().cache_prefetches, 1u);     // But not fetched twice.
  // A read of a touched line is a hit that waits for the rest of the transfer.
  EXPECT_EQ(FirstWord(*spe, EaOf(100)), 100u);
  EXPECT_EQ(spe->counters().cache_hits, 1u);
  EXPECT_EQ(spe->counters().cache_misses, 0u);
  EXPECT_EQ(spe->counters().cache_pending_waits, 1u);
  EXPECT_TRUE(*spe->cache().TouchReport(EaOf(102)));
  EXPECT_EQ(spe->counters().cache_touches, 3u);
}

TEST_F(SoftwareCacheTest, FillsStayInsideTheRegionAndBadReadsFail) {
  // Three quadwords starting mid-line: the line fill must not read past them.
  QuadArray small(16);
  const Quad* begin = &small[3];
  MainMemory memory;
  ASSERT_TRUE(memory.Register(begin, 3 * sizeof(Quad), "small").ok());
  auto spe = MakeSpe(memory);
  absl::StatusOr<Quad> q = spe->cache().ReadValue<Quad>(Ea(&small[5]));
  ASSERT_TRUE(q.ok()) << q.status();
  EXPECT_EQ(q->w[0], 5u);
  EXPECT_LE(spe->counters().dma_get_bytes, 3 * sizeof(Quad));

  EXPECT_EQ(spe->cache().Read(Ea(&small[6]), 16).status().code(), absl::StatusCode::kOutOfRange);
  auto spe2 = MakeSpe(memory_);
  const uint64_t line_end = (EaOf(0) | 127) + 1;
  EXPECT_EQ(spe2->cache().Read(line_end - 8, 16).status().code(),
            absl::StatusCode::kInvalidArgument);  // Crosses a line.
}

}  // namespace
}  // namespace femsimp::cellsim
