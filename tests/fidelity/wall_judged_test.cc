// The wall rule's guarantee judged from outside the engine: on a part with a thin wall beside a
// thick one, each region's two-sided Hausdorff distance (CGAL, tests/judge) stays within its own
// tolerance, the thin wall's the given share of its thickness, on both back ends and with the
// measured check.
#include <gtest/gtest.h>

#include "engine/simplify.h"
#include "tests/judge/judge.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

struct WallCase {
  const char* name;
  Backend backend;
  DeviationCheck check;
};

class WallJudged : public ::testing::TestWithParam<WallCase> {};

TEST_P(WallJudged, EachWallWithinItsOwnTolerance) {
  const RawMesh input = testing::ShellBesideSolidTorus();  // shell 0.1 thick: group 1
  SimplifyOptions o;
  o.tolerance = 0.05;
  o.tolerance_relative = 0.0;
  o.max_volume_change = 0.0;
  o.max_wall_share = 0.2;
  o.backend = GetParam().backend;
  o.deviation_check = GetParam().check;
  o.threads = 2;
  o.cell.spes = 4;
  const testing::SimplifyRun run = testing::SimplifyChecked(input, o);
  ASSERT_LT(run.output.num_vertices(), input.num_vertices() / 2);
  const double slack = judge::FloatStorageSlack(input);
  const double shell_limit = 0.2 * 0.1, solid_limit = 0.05;
  const auto h =
      judge::GroupHausdorffDistances(input, run.output, judge::HausdorffErrorFor(shell_limit));
  ASSERT_EQ(h.size(), 2u);
  EXPECT_LE(h.at(1).two_sided(), shell_limit + slack);
  EXPECT_LE(h.at(2).two_sided(), solid_limit + slack);
  // The thick torus is not held to the thin wall's tolerance.
  EXPECT_GT(h.at(2).two_sided(), 1.2 * shell_limit);
  EXPECT_FALSE(judge::SelfIntersects(run.output));
  const judge::Topology before = judge::ComputeTopology(input),
                        after = judge::ComputeTopology(run.output);
  EXPECT_EQ(after.components, before.components);
  EXPECT_EQ(after.euler(), before.euler());
  EXPECT_EQ(after.nonmanifold_edges + after.boundary_edges, 0);
}

INSTANTIATE_TEST_SUITE_P(
    Backends, WallJudged,
    ::testing::Values(WallCase{"native", Backend::kNative, DeviationCheck::kMapped},
                      WallCase{"cell", Backend::kCell, DeviationCheck::kMapped},
                      WallCase{"native_measured", Backend::kNative, DeviationCheck::kMeasured}),
    [](const ::testing::TestParamInfo<WallCase>& info) { return info.param.name; });

}  // namespace
}  // namespace femsimp
