#include "engine/enclosed_parts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "engine/mesh.h"
#include "engine/prepare.h"
#include "engine/repair.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

constexpr uint32_t kCore = 1, kCoating = 2;

RawMesh Turned(RawMesh m) {
  for (size_t f = 0; f < m.num_faces(); ++f)
    std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]);
  return m;
}

RawMesh InGroup(RawMesh m, uint32_t group) {
  m.face_groups.assign(m.num_faces(), group);
  return m;
}

// testing::Append, groups too.
void AppendBody(RawMesh& m, const RawMesh& body) {
  std::vector<uint32_t> groups = m.face_groups;
  groups.insert(groups.end(), body.face_groups.begin(), body.face_groups.end());
  testing::Append(m, body, {0, 0, 0});
  m.face_groups = std::move(groups);
}

// A solid torus (tube radius 0.5) inside a coating torus (tube radius 1), each body written
// closed in a group of its own: the core's surface comes twice, facing both ways.
RawMesh CoatedTorus(bool core_first) {
  const RawMesh core = InGroup(testing::MakeTorus(64, 32, 3.0, 0.5), kCore);
  RawMesh coating = InGroup(testing::MakeTorus(64, 32, 3.0, 1.0), kCoating);
  AppendBody(coating, InGroup(Turned(testing::MakeTorus(64, 32, 3.0, 0.5)), kCoating));
  RawMesh both = core_first ? core : coating;
  AppendBody(both, core_first ? coating : core);
  return both;
}

// The volume the faces of one group enclose.
double GroupVolume(const RawMesh& m, uint32_t group) {
  RawMesh only;
  only.positions = m.positions;
  for (size_t f = 0; f < m.num_faces(); ++f)
    if (m.face_groups[f] == group)
      only.triangles.insert(only.triangles.end(), &m.triangles[3 * f], &m.triangles[3 * f + 3]);
  return testing::SignedVolume(only);
}

struct PartsRun {
  RepairReport report;
  SimplifyResult result;
  RawMesh output;
};

// PrepareMesh, Simplify and OutputMesh, as the CLI runs them.
PartsRun SimplifyParts(const RawMesh& input, const SimplifyOptions& options) {
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(input, RepairOptions{});
  EXPECT_TRUE(prepared.ok()) << prepared.status();
  if (!prepared.ok()) return {};
  absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, options);
  EXPECT_TRUE(result.ok()) << result.status();
  absl::StatusOr<RawMesh> out =
      OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
  EXPECT_TRUE(out.ok()) << out.status();
  if (!result.ok() || !out.ok()) return {};
  return {prepared->report, *std::move(result), *std::move(out)};
}

// Whichever body comes first, the shared surface is kept once, each body is a part of its own
// volume, and the output has each body closed in its group again, the surface written twice.
TEST(EnclosedParts, ABodyInsideAnotherSharingItsSurfaceIsAPart) {
  for (const bool core_first : {true, false}) {
    SCOPED_TRACE(core_first ? "core first" : "coating first");
    const RawMesh input = CoatedTorus(core_first);
    const double core_in = GroupVolume(input, kCore), coating_in = GroupVolume(input, kCoating);
    SimplifyOptions options;
    options.ratio = 0.3;
    const PartsRun run = SimplifyParts(input, options);
    EXPECT_EQ(run.report.count(RepairKind::kSharedShell), 1u);
    EXPECT_EQ(run.report.count(RepairKind::kSharedShellLeft), 0u);
    ASSERT_EQ(run.result.parts.size(), 2u);
    EXPECT_NEAR(run.result.parts[0].input, coating_in, 1e-9 * coating_in);
    EXPECT_NEAR(run.result.parts[1].input, core_in, 1e-9 * core_in);
    EXPECT_NEAR(run.result.input_mass.measure, core_in + coating_in, 1e-9 * coating_in);
    const double core_out = GroupVolume(run.output, kCore),
                 coating_out = GroupVolume(run.output, kCoating);
    EXPECT_NEAR(run.result.parts[0].output, coating_out, 1e-6 * coating_in);
    EXPECT_NEAR(run.result.parts[1].output, core_out, 1e-6 * core_in);
    EXPECT_LT(run.output.num_vertices(), input.num_vertices() / 2);
  }
}

// The volume budget holds each body, not only their sum (the core's volume from its own group
// in the output); without it the core's facets coarsen past it.
TEST(EnclosedParts, EachBodyKeepsItsVolumeWithinTheBudget) {
  const RawMesh input = CoatedTorus(false);
  const double core_in = GroupVolume(input, kCore), coating_in = GroupVolume(input, kCoating);
  for (const double budget : {0.001, 0.0}) {
    SimplifyOptions options;
    options.ratio = 0.1;
    options.max_volume_change = budget;
    const PartsRun run = SimplifyParts(input, options);
    const double core = GroupVolume(run.output, kCore) / core_in - 1,
                 coating = GroupVolume(run.output, kCoating) / coating_in - 1;
    std::printf("budget %g: %zu -> %zu vertices, core %+.4f%%, coating %+.4f%%\n", budget,
                input.num_vertices(), run.output.num_vertices(), 100 * core, 100 * coating);
    if (budget > 0) {
      EXPECT_LE(std::fabs(core), budget);
      EXPECT_LE(std::fabs(coating), budget);
    } else {
      EXPECT_GT(std::fabs(core), 0.001);
    }
  }
}

// Three layers (a core, a middle layer, a coating), each written closed in its group: both inner
// surfaces come twice. The middle surface counts twice in the depth of what lies inside it, so
// the core's surface faces into the core, and each layer is a part of its own volume.
TEST(EnclosedParts, EachLayerOfACoatedCoreIsAPart) {
  constexpr uint32_t kMiddle = 3;
  RawMesh layers = InGroup(testing::MakeTorus(64, 32, 3.0, 1.0), kCoating);
  AppendBody(layers, InGroup(Turned(testing::MakeTorus(64, 32, 3.0, 0.7)), kCoating));
  AppendBody(layers, InGroup(testing::MakeTorus(64, 32, 3.0, 0.7), kMiddle));
  AppendBody(layers, InGroup(Turned(testing::MakeTorus(64, 32, 3.0, 0.4)), kMiddle));
  AppendBody(layers, InGroup(testing::MakeTorus(64, 32, 3.0, 0.4), kCore));
  SimplifyOptions options;
  options.ratio = 0.3;
  const PartsRun run = SimplifyParts(layers, options);
  EXPECT_EQ(run.report.count(RepairKind::kSharedShell), 2u);
  EXPECT_EQ(run.report.count(RepairKind::kSharedShellLeft), 0u);
  EXPECT_EQ(run.report.count(RepairKind::kFlippedFacet), 0u);
  ASSERT_EQ(run.result.parts.size(), 3u);
  const double total =
      GroupVolume(layers, kCoating) + GroupVolume(layers, kMiddle) + GroupVolume(layers, kCore);
  EXPECT_NEAR(run.result.input_mass.measure, total, 1e-9 * total);
  for (const uint32_t group : {kCoating, kMiddle, kCore}) {
    SCOPED_TRACE(group);
    const double in = GroupVolume(layers, group), now = GroupVolume(run.output, group);
    EXPECT_GT(now, 0.99 * in);
    const auto& parts = run.result.parts;
    EXPECT_TRUE(std::any_of(parts.begin(), parts.end(), [&](const auto& p) {
      return std::fabs(p.input - in) < 1e-9 * in && std::fabs(p.output - now) < 1e-6 * in;
    }));
  }
}

// A core that holds a cavity of its own: the cavity's wall lies inside the shared surface and
// faces into the cavity, and the core's part leaves the cavity out.
TEST(EnclosedParts, ACoreWithACavityIsAPartWithoutIt) {
  RawMesh coated = InGroup(testing::MakeTorus(64, 32, 3.0, 1.0), kCoating);
  AppendBody(coated, InGroup(Turned(testing::MakeTorus(64, 32, 3.0, 0.6)), kCoating));
  AppendBody(coated, InGroup(testing::MakeTorus(64, 32, 3.0, 0.6), kCore));
  AppendBody(coated, InGroup(Turned(testing::MakeTorus(64, 32, 3.0, 0.3)), kCore));
  const double core = GroupVolume(coated, kCore), coating = GroupVolume(coated, kCoating);
  const PartsRun run = SimplifyParts(coated, SimplifyOptions{});
  EXPECT_EQ(run.report.count(RepairKind::kSharedShell), 1u);
  EXPECT_EQ(run.report.count(RepairKind::kReversedComponent), 0u);
  ASSERT_EQ(run.result.parts.size(), 2u);
  EXPECT_NEAR(run.result.parts[0].input, coating, 1e-9 * coating);
  EXPECT_NEAR(run.result.parts[1].input, core, 1e-9 * core);
  EXPECT_NEAR(run.result.input_mass.measure, core + coating, 1e-9 * coating);
  EXPECT_NEAR(GroupVolume(run.output, kCore), run.result.parts[1].output, 1e-6 * core);
}

// A body written twice facing both ways with no body around it, and a cavity written once,
// stay as they were: no parts.
TEST(EnclosedParts, NoPartsWithoutABodyAround) {
  RawMesh twice = testing::MakeTorus(32, 16, 3.0, 1.0);
  testing::Append(twice, Turned(testing::MakeTorus(32, 16, 3.0, 1.0)), {0, 0, 0});
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(twice, RepairOptions{});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  EXPECT_EQ(prepared->report.count(RepairKind::kSharedShell), 0u);
  EXPECT_TRUE(prepared->mesh.sides().empty());

  RawMesh hollow = testing::MakeTorus(32, 16, 3.0, 1.0);
  testing::Append(hollow, Turned(testing::MakeTorus(32, 16, 3.0, 0.5)), {0, 0, 0});
  prepared = PrepareMesh(hollow, RepairOptions{});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  EXPECT_EQ(prepared->report.count(RepairKind::kSharedShell), 0u);
  EXPECT_TRUE(prepared->mesh.sides().empty());
}

}  // namespace
}  // namespace femsimp
