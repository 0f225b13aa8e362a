#include "cellsim/dma_engine.h"

#include <cstring>
#include <vector>

#include "cellsim/runtime.h"
#include "cellsim/spe_context.h"
#include "gtest/gtest.h"
#include "tests/support/cellsim.h"

namespace femsimp::cellsim {
namespace {

using testing::MakeSpe;
using testing::Quad;
using testing::QuadArray;

class DmaEngineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = QuadArray(2048);  // 32 KiB.
    ASSERT_TRUE(memory_.Register(data_.data(), data_.bytes(), "data").ok());
    spe_ = MakeSpe(memory_);
    ASSERT_NE(spe_, nullptr);
    absl::StatusOr<std::byte*> buf = spe_->local_store().Allocate(16 * 1024, 128, "dma buffer");
    ASSERT_TRUE(buf.ok());
    buf_ = *buf;
  }
  uint64_t EaOf(size_t quad) { return Ea(&data_[quad]); }

  QuadArray data_{0};
  MainMemory memory_;
  std::unique_ptr<SpeContext> spe_;
  std::byte* buf_ = nullptr;
};

TEST_F(DmaEngineTest, GetAndPutMoveDataAndAreCounted) {
  DmaEngine& dma = spe_->dma();
  ASSERT_TRUE(dma.Get(buf_, EaOf(10), 64, 0).ok());
  Quad q[4];
  std::memcpy(q, buf_, sizeof(q));
  EXPECT_EQ(q[0].w[0], 10u);
  EXPECT_EQ(q[3].w[3], 16u);

  q[0].w[0] = 777;
  std::memcpy(buf_, q, sizeof(q));
  ASSERT_TRUE(dma.Put(buf_, EaOf(100), 64, 1).ok());
  ASSERT_TRUE(dma.WaitTagMask(0b11).ok());
  EXPECT_EQ(data_[100].w[0], 777u);
  EXPECT_EQ(data_[103].w[3], 16u);

  const SpeCounters& c = spe_->counters();
  EXPECT_EQ(c.dma_gets, 1u);
  EXPECT_EQ(c.dma_puts, 1u);
  EXPECT_EQ(c.DmaBytes(), 128u);
  EXPECT_EQ(c.dma_waits, 1u);
}

TEST_F(DmaEngineTest, RejectsBadRequests) {
  DmaEngine& dma = spe_->dma();
  auto code = [](const absl::StatusOr<uint64_t>& r) { return r.status().code(); };
  const auto kInvalid = absl::StatusCode::kInvalidArgument;
  EXPECT_EQ(code(dma.Get(buf_, EaOf(0) + 8, 16, 0)), kInvalid);          // Misaligned EA.
  EXPECT_EQ(code(dma.Get(buf_ + 4, EaOf(0), 16, 0)), kInvalid);          // Misaligned LS.
  EXPECT_EQ(code(dma.Get(buf_, EaOf(0), 24, 0)), kInvalid);              // Not a multiple of 16.
  EXPECT_EQ(code(dma.Get(buf_, EaOf(0), 0, 0)), kInvalid);               // Empty.
  EXPECT_EQ(code(dma.Get(buf_, EaOf(0), 16 * 1024 + 16, 0)), kInvalid);  // Over 16 KiB.
  EXPECT_EQ(code(dma.Put(buf_, EaOf(0), 16, 32)), kInvalid);             // Tag out of range.
  Quad host_stack{};
  EXPECT_EQ(code(dma.Put(&host_stack, EaOf(0), 16, 0)), kInvalid);  // Not local store.
  EXPECT_EQ(code(dma.Get(buf_, EaOf(2047), 32, 0)), absl::StatusCode::kOutOfRange);  // Past end.
  Quad unregistered{};
  EXPECT_EQ(code(dma.Get(buf_, Ea(&unregistered), 16, 0)), absl::StatusCode::kOutOfRange);

  absl::Status s = dma.Get(buf_, EaOf(0) + 8, 16, 0).status();
  EXPECT_NE(s.message().find("not 16-byte aligned"), std::string::npos) << s;
  EXPECT_EQ(spe_->counters().DmaTransfers(), 0u);          // Nothing moved.
  EXPECT_TRUE(dma.Get(buf_, EaOf(0), 16 * 1024, 0).ok());  // The maximum is fine.
}

TEST_F(DmaEngineTest, LatencyAndBandwidthModel) {
  const CostModel& cost = spe_->config().cost;
  DmaEngine& dma = spe_->dma();
  const uint64_t t0 = spe_->Now();
  absl::StatusOr<uint64_t> done = dma.Get(buf_, EaOf(0), 1024, 5);
  ASSERT_TRUE(done.ok());
  const uint64_t issued = t0 + cost.dma_issue_cycles;
  EXPECT_EQ(*done, issued + cost.dma_latency_cycles + 1024 / cost.dma_bytes_per_cycle);
  EXPECT_EQ(dma.CompletedTagMask(1u << 5), 0u);
  ASSERT_TRUE(dma.WaitTagMask(1u << 5).ok());
  EXPECT_EQ(spe_->Now(), *done);
  EXPECT_EQ(spe_->counters().dma_stall_cycles, *done - issued);
  EXPECT_EQ(dma.CompletedTagMask(1u << 5), 1u << 5);
  // Waiting again costs nothing.
  ASSERT_TRUE(dma.WaitTagMask(1u << 5).ok());
  EXPECT_EQ(spe_->Now(), *done);
  EXPECT_EQ(spe_->counters().ModeledCycles(), spe_->Now() - t0);
}

TEST_F(DmaEngineTest, TagGroupsAreWaitedForSeparately) {
  DmaEngine& dma = spe_->dma();
  absl::StatusOr<uint64_t> big = dma.Get(buf_, EaOf(0), 16 * 1024, 1);
  ASSERT_TRUE(big.ok());
  absl::StatusOr<uint64_t> small = dma.Put(buf_, EaOf(0), 16, 2);  // Other channel.
  ASSERT_TRUE(small.ok());
  ASSERT_LT(*small, *big);
  ASSERT_TRUE(dma.WaitTagMask(1u << 2).ok());
  EXPECT_EQ(spe_->Now(), *small);  // Did not wait for tag 1.
  EXPECT_EQ(dma.CompletedTagMask((1u << 1) | (1u << 2)), 1u << 2);
  ASSERT_TRUE(dma.WaitTagMask((1u << 1) | (1u << 2)).ok());
  EXPECT_EQ(spe_->Now(), *big);
}

TEST_F(DmaEngineTest, FencedRequestsAreOrderedAfterTheirTagGroup) {
  DmaEngine& dma = spe_->dma();
  absl::StatusOr<uint64_t> big = dma.Get(buf_, EaOf(0), 16 * 1024, 0);
  ASSERT_TRUE(big.ok());
  // Unfenced: the put may overtake the get of the same tag.
  absl::StatusOr<uint64_t> plain = dma.Put(buf_, EaOf(0), 16, 0);
  ASSERT_TRUE(plain.ok());
  EXPECT_LT(*plain, *big);
  // A fence in another tag group is not held back by tag 0.
  absl::StatusOr<uint64_t> other = dma.PutF(buf_ + 1024, EaOf(2), 16, 7);
  ASSERT_TRUE(other.ok());
  EXPECT_LT(*other, *big);
  // Fenced: starts only after everything earlier in tag 0 has completed.
  absl::StatusOr<uint64_t> fenced = dma.PutF(buf_, EaOf(1), 16, 0);
  ASSERT_TRUE(fenced.ok());
  EXPECT_GE(*fenced, *big + spe_->config().cost.dma_latency_cycles);
  EXPECT_EQ(dma.TagCompletionCycle(0), *fenced);
}

// Writers put and readers fetch the same quadwords with no synchronisation at all, as SPEs do
// on neighbouring mesh elements: the copies must not race (ThreadSanitizer), and every 8-byte
// half read must be one that some put wrote.
TEST(DmaConcurrencyTest, UnsynchronisedTrafficIsRaceFree) {
  QuadArray data(32);
  for (size_t i = 0; i < data.size(); ++i) data[i] = Quad{{0, 0, 0, 0}};
  RuntimeConfig config;
  config.num_spes = 4;
  config.spe.cache.size_bytes = 16 * 1024;
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(config);
  ASSERT_TRUE(rt.ok()) << rt.status();
  ASSERT_TRUE((*rt)->RegisterMainMemory(data.data(), data.bytes(), "data").ok());
  std::vector<int> torn_halves(config.num_spes, 0);
  absl::Status s = (*rt)->Run([&](SpeContext& spe) {
    constexpr size_t kBytes = 32 * sizeof(Quad);
    absl::StatusOr<std::byte*> buf = spe.local_store().Allocate(kBytes);
    if (!buf.ok()) return spe.ReportError(buf.status());
    for (uint32_t it = 1; it <= 200; ++it) {
      if (spe.index() % 2 == 0) {
        const uint32_t v = it * 2 + spe.index();
        std::vector<Quad> q(32, Quad{{v, v, v + 1, v + 1}});
        std::memcpy(*buf, q.data(), kBytes);
        if (absl::Status p = spe.dma().Put(*buf, Ea(data.data()), kBytes, 0).status(); !p.ok()) {
          return spe.ReportError(p);
        }
      } else {
        for (size_t i = 0; i < data.size(); ++i) {
          spe.cache().Dirty(Ea(&data[i]));
          absl::StatusOr<Quad> q = spe.cache().ReadValue<Quad>(Ea(&data[i]));
          if (!q.ok()) return spe.ReportError(q.status());
          if (q->w[0] != q->w[1] || q->w[2] != q->w[3]) ++torn_halves[spe.index()];
        }
      }
    }
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(torn_halves, std::vector<int>(config.num_spes, 0));
}

}  // namespace
}  // namespace femsimp::cellsim
