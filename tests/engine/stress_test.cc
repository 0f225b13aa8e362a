// Many 8-context runs on the same mesh: every output must be valid, whatever the interleaving.
#include <gtest/gtest.h>

#include "engine/mesh_checks.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

TEST(Stress, EightContextsManyRunsAllValid) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  const auto topology = TopologyOf(raw);
  for (int run = 0; run < 24; ++run) {
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

}  // namespace
}  // namespace femsimp
