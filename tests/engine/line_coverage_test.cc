// The measured check's hold on feature lines (engine/line_coverage.h): collapses along a crease
// judged by hand, with the line's vertices kept, moved within the tolerance and beyond it, and
// the audit of what the commits built.
#include "engine/line_coverage.h"

#include <gtest/gtest.h>

#include "engine/features.h"

namespace femsimp {
namespace {

// Two unit-wide strips folded at a right angle along the x axis: crease vertices 0..4 at
// (i, 0, 0), one side's 5..9 at (i, 1, 0), the other's 10..14 at (i, 0, 1). The crease and
// the border are feature edges.
Mesh Fold() {
  RawMesh m;
  for (const auto& [y, z] : {std::pair{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}})
    for (int i = 0; i < 5; ++i) m.positions.insert(m.positions.end(), {float(i), y, z});
  for (uint32_t i = 0; i < 4; ++i) {
    const uint32_t c = i, a = 5 + i, b = 10 + i;
    m.triangles.insert(m.triangles.end(), {c, c + 1, a + 1, c, a + 1, a});
    m.triangles.insert(m.triangles.end(), {c, b, b + 1, c, b + 1, c + 1});
  }
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  MarkFeatures(*mesh, 30.0);
  return std::move(*mesh);
}

constexpr double kTolerance = 0.1;

// V slides along the crease onto Vd, leaving L: the edge L - Vd takes the pieces of L - V and
// V - Vd. The crease's vertex i lies at (i, 0, 0); the plan puts L there and Vd at vd_at.
LinePlan Slide(uint32_t l, uint32_t v, uint32_t vd, const DVec3& vd_at) {
  LinePlan plan;
  plan.old_edges[0] = {l, v};
  plan.old_edges[1] = {v, vd};
  plan.old_count = 2;
  plan.fresh_edges[0] = {l, vd};
  plan.fresh_from[0] = {double(l), 0, 0};
  plan.fresh_to[0] = vd_at;
  plan.fresh_count = 1;
  return plan;
}

// V = 2 and Vd = 3 merge at p: 1 - 2 - 3 - 4 becomes 1 - p - 4 (p keeps Vd's id).
LinePlan Merge(const DVec3& p) {
  LinePlan plan;
  plan.old_edges[0] = {1, 2};
  plan.old_edges[1] = {2, 3};
  plan.old_edges[2] = {3, 4};
  plan.old_count = 3;
  plan.fresh_edges[0] = {1, 3};
  plan.fresh_from[0] = {1, 0, 0};
  plan.fresh_to[0] = p;
  plan.fresh_edges[1] = {3, 4};
  plan.fresh_from[1] = p;
  plan.fresh_to[1] = {4, 0, 0};
  plan.fresh_count = 2;
  return plan;
}

TEST(LineCoverage, EveryFeatureEdgeHeldOnceAtTheStart) {
  const Mesh mesh = Fold();
  const LineCoverage lines(mesh, kTolerance);
  // The crease (4 edges) and the border: 2 x 4 outer edges along x, 2 x 2 across the ends.
  EXPECT_EQ(lines.segments(), 4u + 8u + 4u);
  EXPECT_TRUE(lines.Audit().ok()) << lines.Audit();
}

TEST(LineCoverage, SlideAlongAStraightLineKeepsEveryPieceWhole) {
  const Mesh mesh = Fold();
  LineCoverage lines(mesh, kTolerance);
  LinePlan plan = Slide(1, 2, 3, {3, 0, 0});
  uint64_t work = 0;
  ASSERT_TRUE(lines.Judge(&plan, &work));
  ASSERT_EQ(plan.given.size(), 2u);
  for (const auto& [edge, piece] : plan.given) {
    EXPECT_EQ(edge, 0);
    EXPECT_EQ(piece.level, 0);
  }
  lines.Apply(plan);
  EXPECT_TRUE(lines.Audit().ok()) << lines.Audit();
  // The edge 1 - 3 now holds both: sliding 3 onto 4 passes them on again.
  LinePlan next = Slide(1, 3, 4, {4, 0, 0});
  ASSERT_TRUE(lines.Judge(&next, &work));
  EXPECT_EQ(next.given.size(), 3u);
  lines.Apply(next);
  EXPECT_TRUE(lines.Audit().ok()) << lines.Audit();
}

TEST(LineCoverage, SlideThatMovesTheLineTooFarIsRefused) {
  const Mesh mesh = Fold();
  const LineCoverage lines(mesh, kTolerance);
  uint64_t work = 0;
  // The new edge ends 0.15 off the crease: the input point 3 is beyond the tolerance of it.
  LinePlan off = Slide(1, 2, 3, {3, 0.15, 0});
  EXPECT_FALSE(lines.Judge(&off, &work));
  // 0.08 off: within.
  LinePlan near = Slide(1, 2, 3, {3, 0.08, 0});
  EXPECT_TRUE(lines.Judge(&near, &work));
}

TEST(LineCoverage, MergeOffTheLineHalvesThePiecesTheNewEdgesShare) {
  const Mesh mesh = Fold();
  LineCoverage lines(mesh, kTolerance);
  uint64_t work = 0;
  LinePlan far = Merge({2.5, 0.3, 0});
  EXPECT_FALSE(lines.Judge(&far, &work));
  LinePlan near = Merge({2.5, 0.05, 0});
  ASSERT_TRUE(lines.Judge(&near, &work));
  // The piece 2 - 3 lies along both new edges: neither holds all of it, so it is halved.
  bool halved = false;
  for (const auto& [edge, piece] : near.given) halved |= piece.level > 0;
  EXPECT_TRUE(halved);
  lines.Apply(near);
  EXPECT_TRUE(lines.Audit().ok()) << lines.Audit();
}

TEST(LineCoverage, AuditNamesAnInputEdgeNoLineHolds) {
  const Mesh mesh = Fold();
  LineCoverage lines(mesh, kTolerance);
  LinePlan dropped;
  dropped.old_edges[0] = {1, 2};  // rewritten, its piece given to no new edge
  dropped.old_count = 1;
  lines.Apply(dropped);
  const absl::Status audit = lines.Audit();
  EXPECT_EQ(audit.code(), absl::StatusCode::kInternal);
  EXPECT_NE(audit.message().find("from vertex 1 (1, 0, 0) to vertex 2 (2, 0, 0)"),
            std::string::npos)
      << audit;
}

}  // namespace
}  // namespace femsimp
