// The same kernel on the emulated Cell BE: outputs must pass the native back end's checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <vector>

#include "cellsim/cost_model.h"
#include "engine/mesh_checks.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"
#include "tests/support/sanitizers.h"

namespace femsimp {
namespace {

using CellRun = testing::SimplifyRun;

CellRun RunCell(const RawMesh& raw, int spes, int ls_cache_kib, int spe_threads,
                bool topology_only = false) {
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.spes = spes;
  options.cell.ls_cache_kib = ls_cache_kib;
  options.cell.spe_threads = spe_threads;
  options.topology_only = topology_only;
  return testing::SimplifyChecked(raw, options);
}

void ExpectValid(const RawMesh& in, const CellRun& run) {
  ASSERT_TRUE(Mesh::Build(run.output).ok()) << Mesh::Build(run.output).status();
  const auto a = TopologyOf(in), b = TopologyOf(run.output);
  EXPECT_EQ(a.euler(), b.euler());
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(b.boundary_edges, 0);
  EXPECT_LT(run.result.output_vertices, run.result.input_vertices / 2);
  for (const PassStats& p : run.result.passes) {
    ASSERT_TRUE(p.cell.has_value());
    EXPECT_GT(p.modeled_pass_cycles, 0u);
  }
}

class CellSpes : public ::testing::TestWithParam<int> {};

TEST_P(CellSpes, ValidOutputWithTheDefaultCache) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const CellRun run = RunCell(raw, GetParam(), 64, 1);
  ExpectValid(raw, run);
  const CellPassCounters& first = *run.result.passes[0].cell;
  EXPECT_GT(first.cache_hits, 0u);
  EXPECT_GT(first.cache_misses, 0u);
  EXPECT_GT(first.atomic_ops, 0u);
  EXPECT_EQ(run.result.passes[0].cell_per_spe.size(), size_t(GetParam()));
}

TEST_P(CellSpes, ValidOutputWithATinyCacheForcingMissesAndStaleReads) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const CellRun run = RunCell(raw, GetParam(), 1, 1, GetParam() == 8);
  ExpectValid(raw, run);
  EXPECT_LT(run.result.passes[0].cell->hit_ratio(), 0.9);
}

INSTANTIATE_TEST_SUITE_P(Spes, CellSpes, ::testing::Values(1, 8, 32));

TEST(CellBackend, SoftwareThreadsOnAndOffBothValid) {
  const RawMesh raw = testing::LoadTestMesh("femur.off");
  for (int threads : {1, 3}) {
    const CellRun run = RunCell(raw, 4, 16, threads);
    ASSERT_TRUE(Mesh::Build(run.output).ok());
    EXPECT_EQ(TopologyOf(raw).euler(), TopologyOf(run.output).euler());
    uint64_t switches = 0;
    for (const PassStats& p : run.result.passes) switches += p.cell->thread_switches;
    if (threads == 1) {
      EXPECT_EQ(switches, 0u);
    } else {
      EXPECT_GT(switches, 0u);
    }
  }
}

TEST(CellBackend, MoreSpesTakeFewerModeledCycles) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const CellRun one = RunCell(raw, 1, 64, 1), eight = RunCell(raw, 8, 64, 1);
  const PassStats &a = one.result.passes[0], &b = eight.result.passes[0];
  EXPECT_LT(b.modeled_pass_cycles * 2, a.modeled_pass_cycles);
}

// Deterministic rounds keep their SPE program resident through a pass: one launch (the first
// round's fan boxes), then a wake-up and a report for every later round's fan boxes, and a
// hand-off from each round's fan boxes to its removals. The free schedule launches its one
// removal run per pass, and leaves the PPE nothing to do.
TEST(CellBackend, RoundsLaunchOncePerPassAndWakeTheSpesAfter) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const cellsim::CostModel cost;
  for (const bool free : {false, true}) {
    SimplifyOptions options;
    options.backend = Backend::kCell;
    options.cell.spes = 8;
    if (free) options.schedule = Schedule::kFree;
    const CellRun run = testing::SimplifyChecked(raw, options);
    ASSERT_FALSE(run.result.passes.empty());
    for (const PassStats& p : run.result.passes) {
      if (free) {
        EXPECT_EQ(p.rounds, 0u);
        EXPECT_EQ(p.ppe_cycles, 0u) << p.pass;  // the lists to cost merge on the SPEs
        EXPECT_EQ(p.spe_start_cycles, cost.spe_run_overhead_cycles) << p.pass;
      } else {
        ASSERT_GT(p.rounds, 0u) << p.pass;
        EXPECT_EQ(p.spe_start_cycles, cost.spe_run_overhead_cycles +
                                          (p.rounds - 1) * cost.ResidentSyncCycles(8) +
                                          p.rounds * cost.HandOffCycles())
            << p.pass;
      }
      EXPECT_LT(p.spe_start_cycles, p.modeled_pass_cycles) << p.pass;
    }
  }
}

// The free schedule shares its candidates out as a guided run too (chunks of a spatial order,
// each in cost order, taken in modeled time), so its SPEs finish together: every candidate is
// tried once, and the slowest SPE's clock stays within 1 % of the mean (the paper's fixed
// split left 2.9 % here, 6 % at 32 SPEs).
TEST(CellBackend, FreeScheduleSpesFinishTogether) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.spes = 8;
  options.schedule = Schedule::kFree;
  options.max_passes = 1;
  const CellRun run = testing::SimplifyChecked(raw, options);
  ASSERT_EQ(run.result.passes.size(), 1u);
  const PassStats& pass = run.result.passes[0];
  EXPECT_EQ(pass.tried, pass.candidates);
  ASSERT_EQ(pass.cell_per_spe.size(), 8u);
  uint64_t slowest = 0, sum = 0;
  for (const CellPassCounters& spe : pass.cell_per_spe) {
    EXPECT_GT(spe.modeled_cycles, 0u);
    slowest = std::max(slowest, spe.modeled_cycles);
    sum += spe.modeled_cycles;
  }
  EXPECT_LT(static_cast<double>(slowest), 1.01 * static_cast<double>(sum) / 8);
}

// The cell back end runs the same candidate loop as the native one, so it notices a
// cancellation inside a pass, not only between passes.
TEST(CellBackend, CancellationStopsInsideAPassWithAValidMesh) {
  for (int spe_threads : {1, 2}) {
    absl::StatusOr<Mesh> mesh = Mesh::Build(testing::LoadTestMesh("fandisk.off"));
    ASSERT_TRUE(mesh.ok());
    SimplifyOptions options;
    options.backend = Backend::kCell;
    options.cell.spes = 4;
    options.cell.spe_threads = spe_threads;
    SimplifyControl control;
    control.cancelled = testing::CancelOnceRemoving(*mesh);
    absl::StatusOr<SimplifyResult> r = Simplify(*mesh, options, control);
    ASSERT_TRUE(r.ok()) << r.status();
    EXPECT_EQ(r->stop_reason, StopReason::kCancelled);
    ASSERT_EQ(r->passes.size(), 1u);
    // Stopped early in the first pass: far fewer candidates tried than handed out.
    EXPECT_LT(r->passes[0].tried * 4, r->passes[0].candidates) << spe_threads;
    EXPECT_EQ(HalfEdgeInvariantViolation(*mesh), "");
    EXPECT_TRUE(Mesh::Build(mesh->ToRaw()).ok());
  }
}

// Far more SPEs than the paper's 8: the deterministic schedule's output does not depend on the
// SPE count (the pass's sort runs on the SPEs and is checked against the engine's order), and
// the modeled time still falls. ThreadSanitizer runs 64 only: its cost grows with the SPE
// threads (the test took 224 s in CI with 128, 61 s without), and 128 takes no path 64 does
// not.
TEST(CellBackend, ManySpesGiveTheNativeOutput) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  SimplifyOptions native;
  native.threads = 1;
  const CellRun reference = testing::SimplifyChecked(raw, native);
  const CellRun eight = RunCell(raw, 8, 64, 1);
  const std::vector<int> spe_counts =
      testing::kUnderThreadSanitizer ? std::vector<int>{64} : std::vector<int>{64, 128};
  for (int spes : spe_counts) {
    const CellRun run = RunCell(raw, spes, 64, 1);
    ExpectValid(raw, run);
    EXPECT_EQ(run.output.positions, reference.output.positions) << spes;
    EXPECT_EQ(run.output.triangles, reference.output.triangles) << spes;
    ASSERT_EQ(run.result.passes.size(), reference.result.passes.size()) << spes;
    EXPECT_EQ(run.result.passes[0].cell_per_spe.size(), size_t(spes));
    EXPECT_LT(run.result.passes[0].modeled_pass_cycles, eight.result.passes[0].modeled_pass_cycles)
        << spes;
  }
}

// Longer cache lines fetch a fan's neighbours with fewer misses (the mesh is stored in a
// spatial order); the output does not depend on them.
TEST(CellBackend, LongerCacheLinesMissLessWithTheSameOutput) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.spes = 4;
  const CellRun short_lines = testing::SimplifyChecked(raw, options);
  options.cell.ls_cache_line_bytes = 1024;
  const CellRun long_lines = testing::SimplifyChecked(raw, options);
  EXPECT_EQ(long_lines.output.positions, short_lines.output.positions);
  EXPECT_EQ(long_lines.output.triangles, short_lines.output.triangles);
  const auto totals = [](const CellRun& run) {
    CellPassCounters sum;
    for (const PassStats& p : run.result.passes) sum += *p.cell;
    return sum;
  };
  const CellPassCounters a = totals(short_lines), b = totals(long_lines);
  EXPECT_LT(b.cache_misses, a.cache_misses);
  EXPECT_GT(b.hit_ratio(), a.hit_ratio());
  EXPECT_GT(b.dma_bytes, a.dma_bytes);  // each miss moves a longer line
}

TEST(CellBackend, CacheLinesThatDoNotFitAreRejected) {
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.ls_cache_line_bytes = 96;
  EXPECT_NE(ValidateOptions(options).message().find("power of two"), std::string::npos);
  options.cell.ls_cache_line_bytes = 8192;
  options.cell.ls_cache_kib = 16;  // a set of 4 lines is 32 KiB
  EXPECT_NE(ValidateOptions(options).message().find("must fit in ls_cache_kib"), std::string::npos);
}

TEST(CellBackend, CacheThatIsNotAPowerOfTwoIsRejected) {
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.ls_cache_kib = 200;
  EXPECT_NE(ValidateOptions(options).message().find("ls_cache_kib"), std::string::npos);
}

// A local store too small for what the cell back end puts in it fails before the first pass,
// naming what does not fit.
void ExpectLocalStoreRefused(const SimplifyOptions& options, const std::string& naming) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(testing::LoadTestMesh("femur.off"));
  ASSERT_TRUE(mesh.ok());
  absl::StatusOr<SimplifyResult> r = Simplify(*mesh, options);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(r.status().message().find(naming), std::string::npos) << r.status();
}

TEST(CellBackend, CacheAndStacksThatDoNotFitAreRejected) {
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.ls_cache_kib = 128;
  options.cell.spe_threads = 4;
  ExpectLocalStoreRefused(options, "local store");
}

TEST(CellBackend, LocalStoreWithoutRoomForTheSortIsRejected) {
  SimplifyOptions options;
  options.backend = Backend::kCell;
  options.cell.local_store_kib = 136;  // the 64 KiB cache and one 56 KiB stack fit, the sort not
  ExpectLocalStoreRefused(options, "sort");
}

}  // namespace
}  // namespace femsimp
