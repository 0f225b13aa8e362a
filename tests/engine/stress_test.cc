// Many 8-context runs on the same mesh: every output must be valid, whatever the interleaving.
// Under a sanitizer, one run of each option combination (6): under TSan each run takes about
// 14 s of 8 threads on 2 cores (335 s for 24 in CI), and a race or bad access is reported on
// any run that takes its path.
#include <gtest/gtest.h>

#include "engine/mesh_checks.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"
#include "tests/support/sanitizers.h"

namespace femsimp {
namespace {

TEST(Stress, EightContextsManyRunsAllValid) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const auto topology = TopologyOf(raw);
  const int runs = testing::kUnderSanitizer ? 6 : 24;
  for (int run = 0; run < runs; ++run) {
    SimplifyOptions options;
    options.threads = 8;
    options.topology_only = run % 2 == 1;
    options.candidate_fraction = run % 3 == 0 ? 1.0 : 0.9;
    absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
    ASSERT_TRUE(mesh.ok());
    absl::StatusOr<SimplifyResult> result = Simplify(*mesh, options);
    ASSERT_TRUE(result.ok()) << result.status();
    ASSERT_EQ(HalfEdgeInvariantViolation(*mesh), "") << "run " << run;
    const RawMesh out = mesh->ToRaw();
    ASSERT_TRUE(Mesh::Build(out).ok()) << "run " << run << ": " << Mesh::Build(out).status();
    const auto after = TopologyOf(out);
    ASSERT_EQ(after.euler(), topology.euler()) << "run " << run;
    ASSERT_EQ(after.components, topology.components) << "run " << run;
    ASSERT_EQ(after.boundary_edges, 0) << "run " << run;
    for (uint32_t v = 0; v < mesh->vertex_capacity(); ++v)
      ASSERT_EQ(mesh->status()[v].load() & kLockedBit, 0u) << "lock left on " << v;
  }
}

// The paper's lock races with full-edge collapses: vertices move while other contexts read
// their rings, on both back ends (the TSan build runs this too).
TEST(Stress, FreeScheduleFullEdgeCollapsesAllValid) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const auto topology = TopologyOf(raw);
  const int runs = testing::kUnderSanitizer ? 6 : 12;  // 6: every option combination once
  for (int run = 0; run < runs; ++run) {
    SimplifyOptions options;
    options.schedule = Schedule::kFree;
    options.placement = Placement::kOptimal;
    options.tolerance_relative = run % 2 == 0 ? 0.01 : 0.002;
    options.max_volume_change = 0.0005;  // refuses many half-edge collapses: placement rescues
    options.max_inertia_change = run % 2 == 0 ? 0.005 : 0.0;
    options.threads = 8;
    if (run % 3 == 2) {
      options.backend = Backend::kCell;
      options.cell.spes = 6;
    }
    absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
    ASSERT_TRUE(mesh.ok());
    absl::StatusOr<SimplifyResult> result = Simplify(*mesh, options);
    ASSERT_TRUE(result.ok()) << result.status();
    ASSERT_EQ(HalfEdgeInvariantViolation(*mesh), "") << "run " << run;
    EXPECT_LT(result->output_vertices, raw.num_vertices() / 4) << "run " << run;
    EXPECT_LE(result->deviation_bound, result->tolerance_abs) << "run " << run;
    const RawMesh out = mesh->ToRaw();
    ASSERT_TRUE(Mesh::Build(out).ok()) << "run " << run << ": " << Mesh::Build(out).status();
    const auto after = TopologyOf(out);
    ASSERT_EQ(after.euler(), topology.euler()) << "run " << run;
    ASSERT_EQ(after.components, topology.components) << "run " << run;
    for (uint32_t v = 0; v < mesh->vertex_capacity(); ++v)
      ASSERT_EQ(mesh->status()[v].load() & kLockedBit, 0u) << "lock left on " << v;
  }
}

}  // namespace
}  // namespace femsimp
