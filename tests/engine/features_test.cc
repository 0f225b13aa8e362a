#include "engine/features.h"

#include <gtest/gtest.h>

#include <vector>

#include "engine/mesh.h"
#include "engine/worker_pool.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

struct Marks {
  FeatureSummary summary;
  std::vector<uint32_t> flags, status;
};

Marks Marked(const RawMesh& raw, WorkerPool* pool) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  Marks marks;
  marks.summary = MarkFeatures(*mesh, 30.0, {}, pool);
  for (uint32_t h = 0; h < mesh->halfedge_capacity(); ++h)
    marks.flags.push_back(mesh->halfedges()[h].flags);
  for (uint32_t v = 0; v < mesh->vertex_capacity(); ++v)
    marks.status.push_back(mesh->status()[v].load());
  return marks;
}

// Meshes of more half-edges than one chunk (64Ki), so that the contexts share them.
TEST(MarkFeatures, ContextsMarkWhatOneMarks) {
  const RawMesh box = testing::MakeBox({1.0, 2.0, 3.0}, {60, 60, 60});  // 43,200 faces
  const RawMesh grid = testing::FlatGrid(200);                          // 80,000 faces, open
  for (const RawMesh* raw : {&box, &grid}) {
    const Marks alone = Marked(*raw, nullptr);
    for (int contexts : {2, 3}) {
      WorkerPool pool(contexts);
      const Marks shared = Marked(*raw, &pool);
      EXPECT_EQ(shared.summary.feature_edges, alone.summary.feature_edges) << contexts;
      EXPECT_EQ(shared.summary.boundary_edges, alone.summary.boundary_edges) << contexts;
      EXPECT_EQ(shared.summary.corner_vertices, alone.summary.corner_vertices) << contexts;
      EXPECT_EQ(shared.flags, alone.flags) << contexts;
      EXPECT_EQ(shared.status, alone.status) << contexts;
    }
  }
  // The box's twelve edges of 60 segments and its eight corners; the grid's border of 4 x 200
  // edges and its four corners.
  const Marks b = Marked(box, nullptr), g = Marked(grid, nullptr);
  EXPECT_EQ(b.summary.feature_edges, 12u * 60u);
  EXPECT_EQ(b.summary.boundary_edges, 0u);
  EXPECT_EQ(b.summary.corner_vertices, 8u);
  EXPECT_EQ(g.summary.feature_edges, 800u);
  EXPECT_EQ(g.summary.boundary_edges, 800u);
  EXPECT_EQ(g.summary.corner_vertices, 4u);
}

// Marks made at a wider angle are undone at a narrower one: a corner of before is freed.
TEST(MarkFeatures, MarkingAgainReplacesTheMarks) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(testing::MakeBox({1.0, 1.0, 1.0}, {4, 4, 4}));
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  WorkerPool pool(2);
  EXPECT_EQ(MarkFeatures(*mesh, 30.0, {}, &pool).corner_vertices, 8u);
  const FeatureSummary none = MarkFeatures(*mesh, 120.0, {}, &pool);
  EXPECT_EQ(none.feature_edges, 0u);
  EXPECT_EQ(none.corner_vertices, 0u);
  for (uint32_t v = 0; v < mesh->vertex_capacity(); ++v)
    EXPECT_EQ(mesh->status()[v].load(), kRemovable) << v;
}

TEST(MarkFeatures, StopsWhenCancelled) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(testing::FlatGrid(200));
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  WorkerPool pool(2);
  const FeatureSummary summary = MarkFeatures(
      *mesh, 30.0, [] { return true; }, &pool);
  EXPECT_EQ(summary.feature_edges, 0u);
  EXPECT_EQ(summary.corner_vertices, 0u);
}

}  // namespace
}  // namespace femsimp
