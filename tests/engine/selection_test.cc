// The pass selection: after the first pass it looks only at the vertices that can be removable
// (engine/selection.h), and must select exactly what a scan of every vertex selects.
#include "engine/selection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/features.h"
#include "engine/kernel.h"
#include "engine/mechanics.h"
#include "engine/port.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

struct PassesRun {
  int passes = 0;
  size_t requeued = 0;                // vertices the kernels logged, over the run
  size_t retried = 0;                 // selected on a reconsideration pass while awaiting a retry
  size_t smallest_late = ~size_t{0};  // the smallest selection after the first pass
};

// Runs passes as the pass driver does (select, remove the first 90 % in cost order, requeue),
// checking every selection against a fresh selection's scan of every vertex.
PassesRun RunPasses(const RawMesh& raw, int threads, bool scatter) {
  Mesh mesh = *Mesh::Build(raw);
  SimplifyOptions options;
  // A tight volume budget refuses collapses beyond their fans: those wait for reconsideration.
  options.max_volume_change = 2e-3;
  MarkFeatures(mesh, options.feature_angle_deg);
  RuleSetup setup;
  setup.cos_feature = std::cos(options.feature_angle_deg * std::numbers::pi / 180.0);
  setup.closed = true;
  const MassProperties mass = MeasureMass(mesh, true, setup.mass_origin);
  setup.mass = &mass;
  const FieldResultants resultants;
  setup.resultants = &resultants;
  const RuleSet rules = RuleSet::Build(options, setup);
  WorkerPool pool(threads);
  const GaussianCurvatureCost cost;
  CandidateSelection selection(mesh, pool, cost, scatter, /*retry_all=*/false);
  RemovalBudget budget;
  budget.alive = static_cast<int64_t>(mesh.CountLiveVertices());
  NativePort port(mesh);
  PassesRun run;
  for (int pass = 1; pass <= 60; ++pass) {
    const bool reconsider = pass > 1 && (pass - 1) % 3 == 0;
    size_t awaiting = 0;
    for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v)
      awaiting += mesh.status()[v].load() == (kNotRemovable | kRetryBit);
    double busy = 0.0;
    const std::vector<uint32_t> sorted = selection.Select(
        reconsider, [] { return false; }, &busy);
    CandidateSelection scan(mesh, pool, cost, scatter, /*retry_all=*/false);
    EXPECT_EQ(scan.Select(
                  reconsider, [] { return false; }, &busy),
              sorted)
        << "pass " << pass;
    if (reconsider) run.retried += awaiting;
    if (sorted.empty()) break;
    ++run.passes;
    if (pass > 1) run.smallest_late = std::min(run.smallest_late, sorted.size());
    KernelStats stats;
    RemovalKernel<NativePort> kernel(port, rules, /*quadric=*/false, budget, stats,
                                     /*placement=*/false, /*requeue_changed=*/true);
    const size_t count = static_cast<size_t>(std::ceil(0.9 * double(sorted.size())));
    for (size_t i = 0; i < count; ++i) kernel.TryRemove(sorted[i]);
    run.requeued += stats.requeued.size();
    selection.requeued()->insert(selection.requeued()->end(), stats.requeued.begin(),
                                 stats.requeued.end());
  }
  return run;
}

TEST(Selection, LaterPassesSelectWhatAScanOfEveryVertexSelects) {
  const PassesRun run = RunPasses(testing::LoadTestMesh("fandisk.off"), 1, /*scatter=*/false);
  EXPECT_GT(run.passes, 5);
  EXPECT_GT(run.requeued, 0u);
  EXPECT_GT(run.retried, 0u);  // reconsideration found vertices a rule beyond the fan refused
  EXPECT_LT(run.smallest_late, 6475u / 10);
}

TEST(Selection, TheSameOnTwoContextsAndInTheRoundsOrder) {
  const PassesRun run = RunPasses(testing::MakeTorus(48, 24), 2, /*scatter=*/true);
  EXPECT_GT(run.passes, 5);
  EXPECT_GT(run.requeued, 0u);
}

}  // namespace
}  // namespace femsimp
