// Facets crossing each other taken out and closed again by the repair stage
// (engine/crossing_repair.h): a vertex written wrongly through the part's far wall, two such
// side by side, and what is left alone (two bodies overlapping).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/crossing_repair.h"
#include "engine/crossings.h"
#include "engine/mesh_checks.h"
#include "engine/repair.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::Append;
using testing::MakeBox;
using testing::SignedVolume;

#define EXPECT_HAS(text, part)                               \
  EXPECT_NE(std::string(text).find(part), std::string::npos) \
      << "missing: " << (part) << "\nin: " << (text)

// A 4 x 4 x 1 box of 4 x 4 x 1 cells; face group 1 on its top (z = 1), 0 elsewhere.
RawMesh Slab() {
  RawMesh box = MakeBox({4, 4, 1}, {4, 4, 1});
  box.face_groups.resize(box.num_faces());
  for (size_t f = 0; f < box.num_faces(); ++f) {
    bool top = true;
    for (int c = 0; c < 3; ++c) top &= box.positions[3 * size_t{box.triangles[3 * f + c]} + 2] == 1;
    box.face_groups[f] = top ? 1 : 0;
  }
  return box;
}

// The top's vertex at (x, y, 1).
uint32_t TopVertex(const RawMesh& m, float x, float y) {
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    if (m.positions[3 * v] == x && m.positions[3 * v + 1] == y && m.positions[3 * v + 2] == 1)
      return v;
  ADD_FAILURE() << "no top vertex at " << x << ", " << y;
  return 0;
}

std::string Records(const RepairReport& r, RepairKind kind) {
  std::string s;
  for (const RepairRecord& rec : r.records)
    if (rec.kind == kind) s += rec.ToString() + "\n";
  return s;
}

TEST(CrossingRepair, AVertexThroughTheFarWallIsTakenOut) {
  RawMesh m = Slab();
  const double volume = SignedVolume(m);
  const uint32_t v = TopVertex(m, 2, 2);
  // A digit lost: through the bottom and half a cell beyond (off the grid's lines, so that its
  // facets pierce the bottom's rather than touch them along edges).
  m.positions[3 * v] = 2.1f;
  m.positions[3 * v + 1] = 2.2f;
  m.positions[3 * v + 2] = -0.5f;
  ASSERT_GT(FindCrossings(m).pairs, 0u);
  const size_t facets = m.num_faces();

  absl::StatusOr<RepairResult> r = RepairMesh(m, RepairOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingRemoved), 1u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 0u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kUnreferencedVertex), 1u);
  EXPECT_HAS(Records(r->report, RepairKind::kCrossingRemoved),
             "6 facets around them taken out (1 vertex with them, the farthest 1.5 off the new "
             "facets) and their rim of 6 edges (2.82843 across: where the vertex belonged is lost) "
             "closed by 4 facets");
  EXPECT_HAS(r->report.Summary(), "took out 1 patch of crossing facets (their holes closed again)");
  EXPECT_EQ(FindCrossings(m).pairs, 0u);
  const SoupTopology t = TopologyOf(m);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.euler(), 2);
  EXPECT_EQ(m.num_faces(), facets - 2);        // a vertex fewer
  EXPECT_NEAR(SignedVolume(m), volume, 1e-9);  // the top is flat: closed as it was
  // The new facets lie in the top and take its group; provenance names top facets.
  for (size_t f = 0; f < m.num_faces(); ++f) {
    bool top = true;
    for (int c = 0; c < 3; ++c) top &= m.positions[3 * size_t{m.triangles[3 * f + c]} + 2] == 1;
    EXPECT_EQ(m.face_groups[f], top ? 1u : 0u) << "facet " << f;
  }
  ASSERT_EQ(r->facet_origin.size(), m.num_faces());
  for (size_t f = facets - 6; f < m.num_faces(); ++f) EXPECT_LT(r->facet_origin[f], facets);
}

TEST(CrossingRepair, TwoVerticesSideBySideAreTakenOutTogether) {
  RawMesh m = Slab();
  const double volume = SignedVolume(m);
  for (float x : {1.0f, 2.0f}) {
    const uint32_t v = TopVertex(m, x, 2);
    m.positions[3 * v] += 0.1f;
    m.positions[3 * v + 1] = 2.2f;
    m.positions[3 * v + 2] = -0.5f;
  }
  ASSERT_GT(FindCrossings(m).pairs, 0u);
  absl::StatusOr<RepairResult> r = RepairMesh(m, RepairOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_GE(r->report.count(RepairKind::kCrossingRemoved), 1u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 0u) << r->report.Details();
  EXPECT_EQ(FindCrossings(m).pairs, 0u);
  const SoupTopology t = TopologyOf(m);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.euler(), 2);
  EXPECT_NEAR(SignedVolume(m), volume, 1e-6 * volume);
}

TEST(CrossingRepair, TwoBodiesOverlappingAreLeftAndSaidSo) {
  RawMesh m = MakeBox({2, 2, 2}, {2, 2, 2});
  Append(m, MakeBox({2, 2, 2}, {2, 2, 2}), {0.5f, 0.6f, 0.7f});
  const std::vector<uint32_t> triangles = m.triangles;
  absl::StatusOr<RepairResult> r = RepairMesh(m, RepairOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingRemoved), 0u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 1u) << r->report.Details();
  EXPECT_HAS(Records(r->report, RepairKind::kCrossingLeft), "two surfaces cross each other (");
  EXPECT_HAS(r->report.Summary(), "left 1 crossing as they were");
  EXPECT_EQ(m.triangles, triangles);
}

// A soup of large random facets crosses itself millions of times: the scan stops at its cap and
// one record says so, instead of listing them all (minutes and gigabytes).
TEST(CrossingRepair, ASoupCrossingItselfEverywhereIsOneRecord) {
  RawMesh soup = testing::RandomSoup(3000, 12345);
  const std::vector<uint32_t> triangles = soup.triangles;
  absl::StatusOr<RepairResult> r = RepairMesh(soup, RepairOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingRemoved), 0u);
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 1u);
  EXPECT_HAS(Records(r->report, RepairKind::kCrossingLeft),
             "more than 100000 face pairs cross; left as they are");
  EXPECT_EQ(soup.triangles, triangles);
}

TEST(CrossingRepair, NothingCrossingIsNoChange) {
  RawMesh m = Slab();
  const RawMesh before = m;
  const UncrossResult r = TakeOutCrossings(m);
  EXPECT_EQ(r.pairs_before, 0u);
  EXPECT_TRUE(r.facet_origin.empty());
  EXPECT_TRUE(r.patches.empty() && r.left.empty());
  EXPECT_EQ(m.triangles, before.triangles);
}

TEST(CrossingRepair, OffInStrictModeAndForTheRecheck) {
  RawMesh m = Slab();
  const uint32_t v = TopVertex(m, 2, 2);
  m.positions[3 * v] = 2.1f;
  m.positions[3 * v + 2] = -0.5f;
  RepairOptions options;
  options.take_out_crossings = false;
  RawMesh kept = m;
  absl::StatusOr<RepairResult> r = RepairMesh(kept, options);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.num_changes(), 0u);
  EXPECT_EQ(kept.triangles, m.triangles);
  options = RepairOptions{};
  options.mode = RepairMode::kOff;  // strict: crossings are not a defect Mesh::Build refuses
  r = RepairMesh(m, options);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.num_changes(), 0u);
}

// A large part with many vertices written wrongly: every one is taken out. Each fill is checked
// against the facets near it (a grid of their boxes); when each check read every facet, the
// repair's budget ran out after about 2e8 / 230,000 fills and left the rest crossing.
TEST(CrossingRepair, ManyVerticesWrittenWronglyOnALargePartAreAllTakenOut) {
  constexpr int kCells = 240;
  RawMesh m = MakeBox({kCells, kCells, 1}, {kCells, kCells, 1});
  const double volume = SignedVolume(m);
  std::map<std::pair<int, int>, uint32_t> top;
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    if (m.positions[3 * v + 2] == 1)
      top[{int(m.positions[3 * v]), int(m.positions[3 * v + 1])}] = v;
  int wrong = 0;
  for (int x = 4; x < kCells - 4; x += 6)
    for (int y = 4; y < kCells - 4; y += 6) {
      const uint32_t v = top.at({x, y});
      m.positions[3 * v] = x + 0.1f;
      m.positions[3 * v + 1] = y + 0.2f;
      m.positions[3 * v + 2] = -0.5f;
      ++wrong;
    }
  ASSERT_GT(size_t(wrong) * m.num_faces(), size_t(3e8));
  ASSERT_GT(FindCrossings(m).pairs, size_t(wrong));
  const size_t facets = m.num_faces();

  absl::StatusOr<RepairResult> r = RepairMesh(m, RepairOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kCrossingRemoved), size_t(wrong));
  EXPECT_EQ(r->report.count(RepairKind::kCrossingLeft), 0u)
      << Records(r->report, RepairKind::kCrossingLeft).substr(0, 2000);
  EXPECT_EQ(FindCrossings(m).pairs, 0u);
  const SoupTopology t = TopologyOf(m);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_EQ(t.euler(), 2);
  EXPECT_EQ(m.num_faces(), facets - 2 * size_t(wrong));  // a vertex fewer each
  EXPECT_NEAR(SignedVolume(m), volume, 1e-6 * volume);   // the top is flat: closed as it was
}

}  // namespace
}  // namespace femsimp
