#include "cellsim/runtime.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/cellsim.h"

namespace femsimp::cellsim {
namespace {

using testing::Quad;
using testing::QuadArray;

RuntimeConfig SmallConfig(int spes) {
  RuntimeConfig config;
  config.num_spes = spes;
  config.spe.cache.size_bytes = 16 * 1024;
  return config;
}

TEST(RuntimeTest, ReusesContextsAcrossManyRuns) {
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(4));
  ASSERT_TRUE(rt.ok()) << rt.status();
  std::vector<int> per_spe(4, 0);  // Each SPE writes only its own slot.
  for (int run = 0; run < 200; ++run) {
    ASSERT_TRUE((*rt)
                    ->Run([&](SpeContext& spe) {
                      ++per_spe[spe.index()];
                      spe.AddComputeCycles(100 + spe.index());
                    })
                    .ok());
  }
  EXPECT_EQ(per_spe, (std::vector<int>{200, 200, 200, 200}));
  EXPECT_EQ((*rt)->runs(), 200u);
  const uint64_t overhead = (*rt)->spe(0).config().cost.spe_run_overhead_cycles;
  EXPECT_EQ((*rt)->last_run_cycles(), overhead + 103);  // The slowest SPE.
  EXPECT_EQ((*rt)->ElapsedCycles(), 200 * (overhead + 103));
  (*rt)->AddPpeCycles(5000);
  EXPECT_EQ((*rt)->ElapsedCycles(), 200 * (overhead + 103) + 5000);
  EXPECT_EQ((*rt)->TotalCounters().compute_cycles, 200u * (100 + 101 + 102 + 103));
  (*rt)->ResetCounters();
  EXPECT_EQ((*rt)->ElapsedCycles(), 0u);
  EXPECT_EQ((*rt)->TotalCounters().ModeledCycles(), 0u);
}

// A resident program is woken and reports back along a tree of the SPEs: its start costs a
// mailbox message each way and two signal hops per level, far less than a launch.
TEST(RuntimeTest, ResidentRunsCostATreeOfSignalsNotALaunch) {
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(5));
  ASSERT_TRUE(rt.ok()) << rt.status();
  const CostModel& cost = (*rt)->spe(0).config().cost;
  const uint64_t hop = cost.dma_latency_cycles + cost.dma_issue_cycles;
  EXPECT_EQ((*rt)->StartCycles(RunStart::kLaunch), cost.spe_run_overhead_cycles);
  EXPECT_EQ((*rt)->StartCycles(RunStart::kResident), 2 * cost.mailbox_cycles + 2 * 3 * hop);
  const auto work = [](SpeContext& spe) { spe.AddComputeCycles(1000 * (spe.index() + 1)); };
  ASSERT_TRUE((*rt)->Run(work, WorkPlan::None(), RunStart::kLaunch).ok());
  EXPECT_EQ((*rt)->last_run_cycles(), cost.spe_run_overhead_cycles + 5000);
  ASSERT_TRUE((*rt)->Run(work, WorkPlan::None(), RunStart::kResident).ok());
  EXPECT_EQ((*rt)->last_run_cycles(), 2 * cost.mailbox_cycles + 6 * hop + 5000);
  EXPECT_EQ((*rt)->ElapsedCycles(),
            cost.spe_run_overhead_cycles + 2 * cost.mailbox_cycles + 6 * hop + 10000);
  EXPECT_EQ(cost.ResidentSyncCycles(1), 2 * cost.mailbox_cycles);
  EXPECT_EQ(cost.ResidentSyncCycles(128), 2 * cost.mailbox_cycles + 14 * hop);
  EXPECT_LT(4 * cost.ResidentSyncCycles(128), cost.spe_run_overhead_cycles);
}

// Each SPE's channel times its own transfers, but the SPEs of a chip share its memory
// interface: four SPEs each streaming 64 KiB take as long as 256 KiB through it, not as one
// SPE's 64 KiB. Sixteen SPEs are two chips, with twice the bandwidth.
TEST(RuntimeTest, MainMemoryBandwidthBoundsARun) {
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(4));
  ASSERT_TRUE(rt.ok()) << rt.status();
  QuadArray data(4096);  // 64 KiB, read by every SPE
  ASSERT_TRUE((*rt)->RegisterMainMemory(data.data(), data.bytes(), "data").ok());
  const CostModel& cost = (*rt)->spe(0).config().cost;
  const auto stream = [&](SpeContext& spe) {
    const LocalStore::Marker mark = spe.local_store().Mark();
    absl::StatusOr<std::byte*> buf = spe.local_store().Allocate(16 * 1024, 128, "buffer");
    if (!buf.ok()) return spe.ReportError(buf.status());
    for (int k = 0; k < 4; ++k)
      if (auto s = spe.dma().Get(*buf, Ea(&data[1024 * k]), 16 * 1024, 0); !s.ok())
        return spe.ReportError(s.status());
    if (absl::Status s = spe.dma().WaitTagMask(1); !s.ok()) return spe.ReportError(s);
    spe.local_store().Release(mark);
  };
  ASSERT_TRUE((*rt)->Run(stream).ok());
  uint64_t slowest = 0;
  for (int i = 0; i < 4; ++i) slowest = std::max(slowest, (*rt)->spe(i).Now());
  EXPECT_LT(slowest, cost.MemoryCycles(4 * 65536, 4));
  EXPECT_EQ((*rt)->last_run_cycles(), cost.spe_run_overhead_cycles + 4 * 65536 / 8);
  EXPECT_EQ((*rt)->memory_bound_runs(), 1u);
  // One SPE alone is held back by its own channel, not by memory.
  ASSERT_TRUE((*rt)
                  ->Run([&](SpeContext& spe) {
                    if (spe.index() == 0) stream(spe);
                  })
                  .ok());
  EXPECT_EQ((*rt)->memory_bound_runs(), 1u);
  EXPECT_GT((*rt)->last_run_cycles(), cost.spe_run_overhead_cycles + 65536 / 8);
  EXPECT_EQ(cost.spes_per_chip, 8);
  EXPECT_EQ(cost.MemoryCycles(4 * 65536, 8), 4 * 65536 / 8);
  EXPECT_EQ(cost.MemoryCycles(4 * 65536, 16), 4 * 65536 / 16);
  EXPECT_EQ(cost.MemoryCycles(4 * 65536, 9), 4 * 65536 / 16);
}

TEST(RuntimeTest, HandsOutWorkPerSpeAndShared) {
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(3));
  ASSERT_TRUE(rt.ok()) << rt.status();
  std::vector<uint32_t> a = {1, 2, 3}, b = {10}, c = {};
  std::vector<std::vector<uint64_t>> seen(3);
  ASSERT_TRUE((*rt)
                  ->Run(
                      [&](SpeContext& spe) {
                        while (auto item = spe.NextWorkItem()) seen[spe.index()].push_back(*item);
                      },
                      WorkPlan::PerSpe({a, b, c}))
                  .ok());
  EXPECT_EQ(seen[0], (std::vector<uint64_t>{1, 2, 3}));
  EXPECT_EQ(seen[1], (std::vector<uint64_t>{10}));
  EXPECT_TRUE(seen[2].empty());

  constexpr uint64_t kItems = 1000;
  std::vector<std::atomic<int>> hits(kItems);
  ASSERT_TRUE((*rt)
                  ->Run(
                      [&](SpeContext& spe) {
                        while (auto item = spe.NextWorkItem()) hits[*item].fetch_add(1);
                      },
                      WorkPlan::Shared(kItems, 7))
                  .ok());
  for (uint64_t i = 0; i < kItems; ++i) EXPECT_EQ(hits[i].load(), 1) << i;
  EXPECT_EQ((*rt)->TotalCounters().work_items, kItems + 4);
}

// The modeled cycles item i costs in the guided tests: uneven, heavy at the start.
uint64_t ItemCost(uint64_t i) { return i < 100 ? 5000 + 37 * (i % 11) : 200 + 13 * (i % 7); }

// What a guided run must do, event by event: the SPE earliest in modeled time (then the lower
// index) visits the shared index (a getllar + putllc) and takes ceil(remaining / 2N) items, at
// most max_chunk; with items published over time (`published`, else all at once) it first
// waits for the next one and takes only those published by then; each SPE ends with one visit
// that finds the index empty. Returns each SPE's items and sets *slowest to the largest clock.
std::vector<std::vector<uint64_t>> GuidedByHand(int spes, uint64_t count, uint64_t visit,
                                                uint64_t max_chunk, uint64_t* slowest,
                                                const std::vector<uint64_t>* published = nullptr) {
  std::vector<std::vector<uint64_t>> items(spes);
  std::vector<uint64_t> clock(spes, 0);
  std::vector<bool> done(spes, false);
  uint64_t next = 0;
  for (;;) {
    int s = -1;
    for (int i = 0; i < spes; ++i)
      if (!done[i] && (s < 0 || clock[i] < clock[s])) s = i;
    if (s < 0) break;
    if (next >= count) {
      clock[s] += visit;
      done[s] = true;
      continue;
    }
    if (published != nullptr) clock[s] = std::max(clock[s], (*published)[next]);
    const uint64_t served = clock[s];
    clock[s] += visit;
    const uint64_t chunk =
        std::min(max_chunk, std::max<uint64_t>(1, (count - next + 2 * spes - 1) / (2 * spes)));
    uint64_t last = std::min(count, next + chunk);
    if (published != nullptr)
      for (uint64_t i = next + 1; i < last; ++i)
        if ((*published)[i] > served) {
          last = i;
          break;
        }
    for (uint64_t i = next; i < last; ++i) {
      items[s].push_back(i);
      clock[s] += ItemCost(i);
    }
    next = last;
  }
  *slowest = *std::max_element(clock.begin(), clock.end());
  return items;
}

// The chunk sizes a caller may lay its items out by: ceil(remaining / 2N), never empty, never
// above the run's largest.
TEST(RuntimeTest, GuidedChunksHalveAnSpesShareOfWhatIsLeft) {
  constexpr uint64_t kAny = WorkPlan::kAnyChunk;
  EXPECT_EQ(GuidedDispenser::ChunkSize(400, 4, kAny), 50u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(401, 4, kAny), 51u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(7, 4, kAny), 1u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(0, 4, kAny), 1u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(10, 1, kAny), 5u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(400, 4, 16), 16u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(40, 4, 16), 5u);
  EXPECT_EQ(GuidedDispenser::ChunkSize(40, 4, 0), 1u);
}

// A guided run splits by modeled time alone: the same items go to the same SPEs however the
// host schedules its threads (here SPE 0's thread dawdles on every item), exactly as the
// event-by-event account above, with or without a largest chunk, and it evens out work a fixed
// split does not.
TEST(RuntimeTest, GuidedRunsSplitInModeledTimeWhateverTheHostDoes) {
  constexpr int kSpes = 4;
  constexpr uint64_t kItems = 400;
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(kSpes));
  ASSERT_TRUE(rt.ok()) << rt.status();
  const CostModel& cost = (*rt)->spe(0).config().cost;
  uint64_t slowest = 0;
  for (const uint64_t max_chunk : {uint64_t{7}, WorkPlan::kAnyChunk}) {
    const std::vector<std::vector<uint64_t>> expected =
        GuidedByHand(kSpes, kItems, cost.IndexVisitCycles(), max_chunk, &slowest);
    for (int dawdle = 0; dawdle < 2; ++dawdle) {
      std::vector<std::vector<uint64_t>> seen(kSpes);
      ASSERT_TRUE((*rt)
                      ->Run(
                          [&](SpeContext& spe) {
                            while (auto item = spe.NextWorkItem()) {
                              if (dawdle && spe.index() == 0)
                                std::this_thread::sleep_for(std::chrono::microseconds(200));
                              seen[spe.index()].push_back(*item);
                              spe.AddComputeCycles(ItemCost(*item));
                            }
                          },
                          WorkPlan::Guided(kItems, max_chunk))
                      .ok());
      EXPECT_EQ(seen, expected) << "dawdle " << dawdle << ", largest chunk " << max_chunk;
      EXPECT_EQ((*rt)->last_run_cycles(), cost.spe_run_overhead_cycles + slowest);
    }
  }
  // The same work split into fixed blocks waits for the SPE with the heavy items.
  std::vector<std::vector<uint32_t>> blocks(kSpes);
  for (uint32_t i = 0; i < kItems; ++i) blocks[i * kSpes / kItems].push_back(i);
  ASSERT_TRUE((*rt)
                  ->Run(
                      [&](SpeContext& spe) {
                        while (auto item = spe.NextWorkItem())
                          spe.AddComputeCycles(ItemCost(*item));
                      },
                      WorkPlan::PerSpe({blocks[0], blocks[1], blocks[2], blocks[3]}))
                  .ok());
  EXPECT_GT((*rt)->last_run_cycles(), cost.spe_run_overhead_cycles + slowest * 3 / 2);
  // No items: every SPE finds the index empty at once.
  ASSERT_TRUE((*rt)
                  ->Run([&](SpeContext& spe) { EXPECT_FALSE(spe.NextWorkItem().has_value()); },
                        WorkPlan::Guided(0))
                  .ok());
}

// Items published over time (as the PPE hands over a round's winners while it still picks
// them): an SPE that asks before the next one is out waits for it, takes only what is out by
// then, and the wait counts in its modeled time; the split still follows the modeled clocks
// alone, whatever the host does.
TEST(RuntimeTest, GuidedRunsWaitForItemsPublishedLater) {
  constexpr int kSpes = 4;
  constexpr uint64_t kItems = 400;
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(kSpes));
  ASSERT_TRUE(rt.ok()) << rt.status();
  const CostModel& cost = (*rt)->spe(0).config().cost;
  std::vector<uint64_t> published(kItems);
  for (uint64_t i = 0; i < kItems; ++i) published[i] = 3000 + 900 * i;  // slower than 4 SPEs
  uint64_t slowest = 0;
  const std::vector<std::vector<uint64_t>> expected = GuidedByHand(
      kSpes, kItems, cost.IndexVisitCycles(), WorkPlan::kAnyChunk, &slowest, &published);
  for (int dawdle = 0; dawdle < 2; ++dawdle) {
    std::vector<std::vector<uint64_t>> seen(kSpes);
    uint64_t waited = 0;
    ASSERT_TRUE((*rt)
                    ->Run(
                        [&](SpeContext& spe) {
                          while (auto item = spe.NextWorkItem()) {
                            if (dawdle && spe.index() == 1)
                              std::this_thread::sleep_for(std::chrono::microseconds(200));
                            seen[spe.index()].push_back(*item);
                            spe.AddComputeCycles(ItemCost(*item));
                          }
                        },
                        WorkPlan::Guided(kItems, WorkPlan::kAnyChunk, published.data()))
                    .ok());
    for (int i = 0; i < kSpes; ++i) waited += (*rt)->spe(i).counters().work_wait_cycles;
    EXPECT_EQ(seen, expected) << "dawdle " << dawdle;
    EXPECT_EQ((*rt)->last_run_cycles(), cost.spe_run_overhead_cycles + slowest);
    // The last item is out at 3000 + 900 * 399: nobody can finish before it.
    EXPECT_GT(slowest, published.back());
    EXPECT_GT(waited, 0u);
  }
}

TEST(RuntimeTest, ReportsTheFirstKernelError) {
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(3));
  ASSERT_TRUE(rt.ok());
  absl::Status s = (*rt)->Run([](SpeContext& spe) {
    if (spe.index() == 2) spe.ReportError(absl::InternalError("boom"));
  });
  EXPECT_EQ(s.code(), absl::StatusCode::kInternal);
  EXPECT_NE(s.message().find("SPE 2: boom"), std::string::npos) << s;
  EXPECT_TRUE((*rt)->Run([](SpeContext&) {}).ok());  // Errors do not stick.
  EXPECT_FALSE(Runtime::Create(SmallConfig(0)).ok());
}

// SPE 0 caches a quadword; SPE 1 changes it in main memory and publishes through a status
// word; SPE 0 still reads its stale line until it dirties it.
TEST(RuntimeTest, StaleLinesAcrossConcurrentSpes) {
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(SmallConfig(2));
  ASSERT_TRUE(rt.ok());
  QuadArray data(8);
  alignas(16) uint32_t flags[4] = {};  // [0]: SPE 0 has read; [1]: SPE 1 has written.
  ASSERT_TRUE((*rt)->RegisterMainMemory(data.data(), data.bytes(), "data").ok());
  ASSERT_TRUE((*rt)->RegisterMainMemory(flags, sizeof(flags), "flags").ok());
  uint32_t before = 0, stale = 0, fresh = 0;
  auto wait_for = [](SpeContext& spe, uint32_t* word) {
    while (*spe.atomic().Load(word) == 0) std::this_thread::yield();
  };
  absl::Status s = (*rt)->Run([&](SpeContext& spe) {
    const uint64_t ea = Ea(&data[2]);
    if (spe.index() == 0) {
      before = spe.cache().ReadValue<Quad>(ea)->w[0];
      (void)spe.atomic().PutLluc(&flags[0], 1);
      wait_for(spe, &flags[1]);
      stale = spe.cache().ReadValue<Quad>(ea)->w[0];
      spe.cache().Dirty(ea);
      ++spe.counters().stale_detections;
      fresh = spe.cache().ReadValue<Quad>(ea)->w[0];
    } else {
      wait_for(spe, &flags[0]);
      absl::StatusOr<std::byte*> buf = spe.local_store().Allocate(16);
      if (!buf.ok()) return spe.ReportError(buf.status());
      Quad q{{42, 0, 0, 0}};
      std::memcpy(*buf, &q, 16);
      (void)spe.dma().Put(*buf, ea, 16, 0);
      (void)spe.atomic().PutLluc(&flags[1], 1);
    }
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(before, 2u);
  EXPECT_EQ(stale, 2u);
  EXPECT_EQ(fresh, 42u);
  EXPECT_EQ((*rt)->TotalCounters().stale_detections, 1u);
  EXPECT_EQ((*rt)->RegisterMainMemory(flags, 4, "again").code(), absl::StatusCode::kAlreadyExists);
}

}  // namespace
}  // namespace femsimp::cellsim
