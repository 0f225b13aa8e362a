#include "cellsim/spe_sort.h"

#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include "gtest/gtest.h"

namespace femsimp::cellsim {
namespace {

// n keys in 16-byte aligned, registered main memory, plus the scratch array.
struct Keys {
  explicit Keys(size_t n) : storage(n + 2), scratch_storage(n + 2), n(n) {
    data = Align(storage.data());
    scratch = Align(scratch_storage.data());
  }
  static uint64_t* Align(uint64_t* p) {
    return reinterpret_cast<uintptr_t>(p) % 16 == 0 ? p : p + 1;
  }
  absl::Status Register(Runtime& rt) {
    if (absl::Status s = rt.RegisterMainMemory(data, n * 8 + 16, "keys"); !s.ok()) return s;
    return rt.RegisterMainMemory(scratch, n * 8 + 16, "scratch");
  }
  std::vector<uint64_t> storage, scratch_storage;
  uint64_t *data, *scratch;
  size_t n;
};

std::unique_ptr<Runtime> MakeRuntime(int spes) {
  RuntimeConfig config;
  config.num_spes = spes;
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(config);
  EXPECT_TRUE(rt.ok()) << rt.status();
  return rt.ok() ? std::move(*rt) : nullptr;
}

// Random keys (with repeats when `range` is small), sorted on `spes` SPEs, compared with
// std::sort.
void ExpectSorts(int spes, size_t n, uint64_t range, uint32_t seed) {
  std::unique_ptr<Runtime> rt = MakeRuntime(spes);
  ASSERT_NE(rt, nullptr);
  Keys keys(n);
  ASSERT_TRUE(keys.Register(*rt).ok());
  std::mt19937_64 rng(seed);
  for (size_t i = 0; i < n; ++i) keys.data[i] = rng() % range;
  std::vector<uint64_t> expected(keys.data, keys.data + n);
  std::sort(expected.begin(), expected.end());
  absl::StatusOr<SpeSortStats> stats = SortOnSpes(*rt, keys.data, keys.scratch, n);
  ASSERT_TRUE(stats.ok()) << stats.status();
  EXPECT_EQ(std::vector<uint64_t>(keys.data, keys.data + n), expected)
      << spes << " SPEs, " << n << " keys";
  EXPECT_EQ(stats->runs, n == 0 ? 0u : uint64_t(1 + stats->levels));
}

TEST(SpeSortTest, SortsAnyCountOnAnySpeCount) {
  for (int spes : {1, 2, 3, 8, 64, 128})
    for (size_t n : {size_t{0}, size_t{2}, size_t{6}, size_t{1000}, size_t{9002}, size_t{40000}})
      ExpectSorts(spes, n, ~uint64_t{0}, static_cast<uint32_t>(spes * 7919 + n));
}

TEST(SpeSortTest, SortsRepeatedKeys) {
  for (int spes : {1, 5, 32}) ExpectSorts(spes, 30000, 17, 11);
}

// One SPE, 2^14 keys: four blocks of 4096 sorted in the local store (12 merge levels each),
// then two merge levels over main memory. Every cycle and byte follows from that work.
TEST(SpeSortTest, ChargesTheWorkDone) {
  std::unique_ptr<Runtime> rt = MakeRuntime(1);
  ASSERT_NE(rt, nullptr);
  const size_t n = 1 << 14;
  Keys keys(n);
  ASSERT_TRUE(keys.Register(*rt).ok());
  for (size_t i = 0; i < n; ++i) keys.data[i] = (i * 2654435761u) % 1000003;
  absl::StatusOr<SpeSortStats> stats = SortOnSpes(*rt, keys.data, keys.scratch, n);
  ASSERT_TRUE(stats.ok()) << stats.status();
  EXPECT_EQ(stats->block_keys, kMaxBlockKeys);
  EXPECT_EQ(stats->levels, 2);
  EXPECT_EQ(stats->merged, n * 12 + n * 2);
  EXPECT_EQ(stats->probes, 0u);  // one SPE never starts inside a pair of runs
  const SpeCounters c = rt->TotalCounters();
  const CostModel cost;
  EXPECT_EQ(c.compute_cycles, stats->merged * cost.sort_merge_cycles);
  // Every key in and out once per level, the block sort's included.
  EXPECT_EQ(c.dma_get_bytes, 3 * n * sizeof(uint64_t));
  EXPECT_EQ(c.dma_put_bytes, 3 * n * sizeof(uint64_t));
  EXPECT_EQ(stats->elapsed_cycles, rt->ElapsedCycles());
  // One launch (the block sort), then the resident program woken for each of 2 merge levels.
  EXPECT_EQ(stats->runs, 3u);
  EXPECT_EQ(stats->elapsed_cycles,
            cost.spe_run_overhead_cycles + 2 * cost.ResidentSyncCycles(1) + rt->spe(0).Now());
  EXPECT_GE(rt->spe(0).Now(), c.compute_cycles);
}

// Many SPEs split every level evenly (merge-path probes where a slice starts inside a pair),
// so the modeled time falls with the SPE count while the total work grows only by the probes.
TEST(SpeSortTest, ScalesWithSpes) {
  const size_t n = 1 << 17;
  std::vector<uint64_t> elapsed;
  for (int spes : {1, 8, 64}) {
    std::unique_ptr<Runtime> rt = MakeRuntime(spes);
    ASSERT_NE(rt, nullptr);
    Keys keys(n);
    ASSERT_TRUE(keys.Register(*rt).ok());
    std::mt19937_64 rng(5);
    for (size_t i = 0; i < n; ++i) keys.data[i] = rng();
    absl::StatusOr<SpeSortStats> stats = SortOnSpes(*rt, keys.data, keys.scratch, n);
    ASSERT_TRUE(stats.ok()) << stats.status();
    EXPECT_TRUE(std::is_sorted(keys.data, keys.data + n));
    if (spes > 1) {
      EXPECT_GT(stats->probes, 0u);
    }
    elapsed.push_back(stats->elapsed_cycles);
  }
  EXPECT_LT(elapsed[1] * 5, elapsed[0]);  // 8 SPEs: more than 5x faster
  EXPECT_LT(elapsed[2] * 4, elapsed[1]);  // 64 SPEs: more than 4x faster again
}

TEST(SpeSortTest, RefusesOddCountsAndUnregisteredMemory) {
  std::unique_ptr<Runtime> rt = MakeRuntime(2);
  ASSERT_NE(rt, nullptr);
  Keys keys(10);
  absl::StatusOr<SpeSortStats> odd = SortOnSpes(*rt, keys.data, keys.scratch, 9);
  EXPECT_EQ(odd.status().code(), absl::StatusCode::kInvalidArgument);
  absl::StatusOr<SpeSortStats> unregistered = SortOnSpes(*rt, keys.data, keys.scratch, 10);
  EXPECT_EQ(unregistered.status().code(), absl::StatusCode::kOutOfRange) << unregistered.status();
}

TEST(SpeSortTest, RefusesALocalStoreWithoutRoom) {
  RuntimeConfig config;
  config.num_spes = 1;
  config.spe.local_store_bytes = 96 * 1024;  // 64 KiB cache + 12 KiB tags leave 20 KiB
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(config);
  ASSERT_TRUE(rt.ok()) << rt.status();
  Keys keys(8192);
  ASSERT_TRUE(keys.Register(**rt).ok());
  absl::StatusOr<SpeSortStats> stats = SortOnSpes(**rt, keys.data, keys.scratch, 8192);
  EXPECT_EQ(stats.status().code(), absl::StatusCode::kResourceExhausted) << stats.status();
}

}  // namespace
}  // namespace femsimp::cellsim
