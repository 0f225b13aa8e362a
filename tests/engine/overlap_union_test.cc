#include "engine/overlap_union.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "engine/crossings.h"
#include "engine/mesh.h"
#include "engine/prepare.h"
#include "engine/repair.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::Append;
using testing::MakeBox;

// Two cubes 2 x 2 x 2 (sides of 3 x 3 squares, so that no corner of one lies on the other), the
// second moved by (1, 1, 1) into the first: the union's volume is 8 + 8 - 1. Face group 1 on the
// first, 2 on the second.
RawMesh CubesOverlapping() {
  RawMesh soup = MakeBox({2, 2, 2}, {3, 3, 3});
  const size_t first = soup.num_faces();
  Append(soup, MakeBox({2, 2, 2}, {3, 3, 3}), {1, 1, 1});
  soup.face_groups.assign(soup.num_faces(), 2);
  std::fill(soup.face_groups.begin(), soup.face_groups.begin() + first, 1);
  return soup;
}

DVec3 Corner(const RawMesh& m, size_t f, int k) {
  const float* p = &m.positions[3 * size_t{m.triangles[3 * f + k]}];
  return {p[0], p[1], p[2]};
}

// How far p lies from the surface of `m`.
double DistanceToSurface(const RawMesh& m, const DVec3& p) {
  double best = INFINITY;
  for (size_t f = 0; f < m.num_faces(); ++f)
    best = std::min(
        best, testing::PointTriangleDistance(p, Corner(m, f, 0), Corner(m, f, 1), Corner(m, f, 2)));
  return best;
}

// Every directed edge used once and its reverse once.
bool ClosedAndOriented(const RawMesh& m) {
  absl::flat_hash_map<uint64_t, int> uses;
  for (size_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      ++uses[uint64_t{m.triangles[3 * f + k]} << 32 | m.triangles[3 * f + (k + 1) % 3]];
  for (const auto& [key, n] : uses)
    if (n != 1 || !uses.contains(key << 32 | key >> 32)) return false;
  return true;
}

TEST(OverlapUnion, TwoCubesBecomeTheirUnion) {
  const RawMesh given = CubesOverlapping();
  const UnionResult u = UniteOverlaps(given);
  ASSERT_EQ(u.united.size(), 1u);
  const RawMesh& mesh = u.mesh;
  EXPECT_TRUE(u.left.empty());
  const UnitedBodies& b = u.united[0];
  EXPECT_EQ(b.bodies, 2u);
  EXPECT_EQ(b.first_facet, 0u);
  EXPECT_EQ(b.facets_before, given.num_faces());
  EXPECT_EQ(b.facets_after, mesh.num_faces());
  EXPECT_GT(b.points_added, 0u);
  EXPECT_NEAR(b.volume_before, 16.0, 1e-9);
  EXPECT_NEAR(b.volume_after, 15.0, 1e-9);
  EXPECT_NEAR(testing::SignedVolume(mesh), 15.0, 1e-5);
  EXPECT_TRUE(ClosedAndOriented(mesh));
  const SoupCrossings c = FindCrossings(mesh);
  EXPECT_EQ(c.pairs, 0u);
  EXPECT_EQ(c.overlaps.pairs, 0u);
  EXPECT_TRUE(Mesh::Build(mesh).ok());

  // Provenance: each facet lies in the facet it names, and keeps that facet's group; kept
  // vertices are where they were.
  ASSERT_EQ(u.facet_origin.size(), mesh.num_faces());
  ASSERT_EQ(u.vertex_origin.size(), mesh.num_vertices());
  ASSERT_EQ(mesh.face_groups.size(), mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t from = u.facet_origin[f];
    EXPECT_EQ(mesh.face_groups[f], given.face_groups[from]);
    RawMesh one;
    one.positions = given.positions;
    one.triangles.assign(&given.triangles[3 * size_t{from}],
                         &given.triangles[3 * size_t{from}] + 3);
    for (int k = 0; k < 3; ++k) EXPECT_LT(DistanceToSurface(one, Corner(mesh, f, k)), 1e-6);
  }
  size_t added = 0;
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    if (u.vertex_origin[v] == kNoUnionSource) {
      ++added;
      continue;
    }
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(mesh.positions[3 * v + i], given.positions[3 * size_t{u.vertex_origin[v]} + i]);
  }
  EXPECT_EQ(added, b.points_added);
}

// A torus through a tilted box, neither in any axis plane: the points where the surfaces cross
// are rounded to floats. The union lies on the two surfaces, closed, crossing nothing, and
// holds less than the two volumes summed and more than either.
TEST(OverlapUnion, ATorusThroughATiltedBox) {
  RawMesh box = testing::TurnedSkew(MakeBox({3, 1.5, 2}, {6, 3, 4}));
  RawMesh soup = testing::MakeTorus(48, 24, 3.0, 1.0);
  Append(soup, box, {1.5f, 0.2f, -0.8f});
  RawMesh torus_alone = testing::MakeTorus(48, 24, 3.0, 1.0);
  const double torus = testing::SignedVolume(torus_alone);
  const double tilted = testing::SignedVolume(box);
  const RawMesh given = soup;
  UnionResult u = UniteOverlaps(soup);
  ASSERT_EQ(u.united.size(), 1u);
  EXPECT_EQ(soup.triangles, given.triangles);  // the union is beside it
  soup = std::move(u.mesh);
  EXPECT_NEAR(u.united[0].volume_before, torus + tilted, 1e-6 * (torus + tilted));
  const double after = testing::SignedVolume(soup);
  EXPECT_NEAR(after, u.united[0].volume_after, 1e-5 * after);
  EXPECT_LT(after, torus + tilted - 0.1);
  EXPECT_GT(after, std::max(torus, tilted) + 0.1);
  EXPECT_TRUE(ClosedAndOriented(soup));
  EXPECT_EQ(FindCrossings(soup).pairs, 0u);
  for (size_t v = 0; v < soup.num_vertices(); ++v) {
    const float* p = &soup.positions[3 * v];
    EXPECT_LT(DistanceToSurface(given, {p[0], p[1], p[2]}), 1e-5) << "vertex " << v;
  }
}

TEST(OverlapUnion, BodiesApartAreNotTouched) {
  RawMesh soup = MakeBox({1, 1, 1}, {1, 1, 1});
  Append(soup, MakeBox({1, 1, 1}, {1, 1, 1}), {3, 0, 0});
  const RawMesh given = soup;
  const UnionResult u = UniteOverlaps(soup);
  EXPECT_TRUE(u.united.empty());
  EXPECT_TRUE(u.left.empty());
  EXPECT_TRUE(u.facet_origin.empty());
  EXPECT_EQ(u.mesh.num_faces(), 0u);
  EXPECT_EQ(soup.positions, given.positions);
  EXPECT_EQ(soup.triangles, given.triangles);
}

// A box crossed by an open sheet: the sheet bounds no volume, so the two stay as they are and
// the result says why.
TEST(OverlapUnion, ASheetThroughABodyIsLeft) {
  RawMesh soup = MakeBox({2, 2, 2}, {2, 2, 2});
  RawMesh sheet = testing::FlatGrid(5);  // the unit square in z = 0
  for (size_t v = 0; v < sheet.num_vertices(); ++v) {
    sheet.positions[3 * v] = sheet.positions[3 * v] * 4 - 1;
    sheet.positions[3 * v + 1] = sheet.positions[3 * v + 1] * 4 - 1;
  }
  Append(soup, sheet, {0, 0, 1.1f});
  const RawMesh given = soup;
  const UnionResult u = UniteOverlaps(soup);
  EXPECT_TRUE(u.united.empty());
  ASSERT_EQ(u.left.size(), 1u);
  EXPECT_EQ(u.left[0].first_facet, 0u);
  EXPECT_NE(u.left[0].reason.find("is not a body a union takes: it is not closed"),
            std::string::npos)
      << u.left[0].reason;
  EXPECT_EQ(soup.triangles, given.triangles);
}

// Through the repair: one record of the union (no crossing left), or, with the option off, the
// crossing reported and left.
TEST(OverlapUnion, RepairUnitesOnlyWhenAsked) {
  RepairOptions options;
  RawMesh plain = CubesOverlapping();
  absl::StatusOr<RepairResult> r = RepairMesh(plain, options);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kUnitedBodies), 0u);
  EXPECT_GT(r->report.count(RepairKind::kCrossingLeft), 0u);

  options.unite_overlaps = true;
  RawMesh united = CubesOverlapping();
  r = RepairMesh(united, options);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kUnitedBodies), 1u);
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 0u);
  EXPECT_EQ(r->report.count(RepairKind::kOverlapLeft), 0u);
  ASSERT_FALSE(r->report.records.empty());
  EXPECT_NE(r->report.Details().find(": 2 bodies exported overlapping united: their 216 facets "
                                     "re-made as "),
            std::string::npos)
      << r->report.Details();
  EXPECT_NE(r->report.Summary().find("united 1 group of overlapping bodies (replaced by their "
                                     "union)"),
            std::string::npos)
      << r->report.Summary();
  ASSERT_EQ(r->facet_origin.size(), united.num_faces());
  EXPECT_NEAR(testing::SignedVolume(united), 15.0, 1e-5);

  // Then simplified: one part, the volume kept within the default budget.
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(CubesOverlapping(), options);
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, SimplifyOptions{});
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_NEAR(result->input_mass.measure, 15.0, 1e-5);
  EXPECT_NEAR(result->output_mass.measure, 15.0, 15.0 * 0.005);
}

// The first cube with a vertex written wrongly: the one at (2/3, 2/3, 0) of its bottom, moved
// through its top wall (and the second cube's bottom) to z = 3.1. That body crosses itself, which
// no union takes: its crossing is taken out first (the vertex with its facets, the bottom closed
// again), then the bodies united.
TEST(OverlapUnion, ABodyWithAVertexWrittenWronglyIsMendedThenUnited) {
  RawMesh soup = CubesOverlapping();
  const size_t first_cube_vertices = MakeBox({2, 2, 2}, {3, 3, 3}).num_vertices();
  size_t spike = first_cube_vertices;
  for (size_t v = 0; v < first_cube_vertices; ++v) {
    const float* p = &soup.positions[3 * v];
    if (std::abs(p[0] - 2.f / 3) < 1e-6f && std::abs(p[1] - 2.f / 3) < 1e-6f && p[2] == 0.f)
      spike = v;
  }
  ASSERT_LT(spike, first_cube_vertices);
  // Off the grid's lines, so that its facets cross the top's inside theirs, not at their edges.
  soup.positions[3 * spike] = 0.61f;
  soup.positions[3 * spike + 1] = 0.73f;
  soup.positions[3 * spike + 2] = 3.1f;

  RepairOptions options;
  options.unite_overlaps = true;
  absl::StatusOr<RepairResult> r = RepairMesh(soup, options);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingRemoved), 1u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kUnitedBodies), 1u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kOverlapLeft), 0u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 0u) << r->report.Details();
  EXPECT_NE(r->report.Details().find("facets of one surface crossed each other"), std::string::npos)
      << r->report.Details();
  EXPECT_TRUE(ClosedAndOriented(soup));
  EXPECT_EQ(FindCrossings(soup).pairs, 0u);
  EXPECT_NEAR(testing::SignedVolume(soup), 15.0, 1e-5);
  ASSERT_EQ(r->facet_origin.size(), soup.num_faces());
  for (uint32_t from : r->facet_origin) EXPECT_LT(from, CubesOverlapping().num_faces());
}

}  // namespace
}  // namespace femsimp
