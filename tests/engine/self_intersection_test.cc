// The self-intersection rule's parts: the triangle test, the face grid's cell locks, and the
// rule on a whole run.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "engine/face_grid.h"
#include "engine/mesh.h"
#include "engine/simplify.h"
#include "engine/triangle_intersection.h"
#include "engine/work_shares.h"
#include "engine/worker_pool.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

Triangle Tri(DVec3 a, DVec3 b, DVec3 c, uint32_t ia, uint32_t ib, uint32_t ic) {
  return Triangle{{a, b, c}, {ia, ib, ic}};
}

TEST(TrianglesIntersect, CrossingAndDisjoint) {
  const Triangle flat = Tri({0, 0, 0}, {2, 0, 0}, {0, 2, 0}, 0, 1, 2);
  const Triangle piercing = Tri({0.5, 0.5, -1}, {0.5, 0.5, 1}, {1.5, 0.2, 0}, 3, 4, 5);
  const Triangle above = Tri({0, 0, 1}, {2, 0, 1}, {0, 2, 1}, 3, 4, 5);
  EXPECT_TRUE(TrianglesIntersect(flat, piercing));
  EXPECT_FALSE(TrianglesIntersect(flat, above));
  // Coplanar and overlapping, no shared vertex.
  const Triangle overlapping = Tri({0.2, 0.2, 0}, {3, 0.2, 0}, {0.2, 3, 0}, 3, 4, 5);
  EXPECT_TRUE(TrianglesIntersect(flat, overlapping));
}

TEST(TrianglesIntersect, SharedEdgeMeetsOnlyWhenFolded) {
  const Triangle a = Tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0, 1, 2);
  // Across the edge (the usual neighbour), bent up out of the plane, or folded back onto a.
  EXPECT_FALSE(TrianglesIntersect(a, Tri({1, 0, 0}, {0, 0, 0}, {0.5, -1, 0}, 1, 0, 3)));
  EXPECT_FALSE(TrianglesIntersect(a, Tri({1, 0, 0}, {0, 0, 0}, {0.5, 0.5, 1}, 1, 0, 3)));
  EXPECT_TRUE(TrianglesIntersect(a, Tri({1, 0, 0}, {0, 0, 0}, {0.3, 0.3, 0}, 1, 0, 3)));
}

TEST(TrianglesIntersect, SharedCornerMeetsOnlyBeyondIt) {
  const Triangle a = Tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0, 1, 2);
  // Two fan neighbours apart: they touch at the corner only.
  EXPECT_FALSE(TrianglesIntersect(a, Tri({0, 0, 0}, {-1, 0, 0}, {0, -1, 0}, 0, 3, 4)));
  // One that passes through a beyond the shared corner.
  EXPECT_TRUE(TrianglesIntersect(a, Tri({0, 0, 0}, {0.3, 0.3, -1}, {0.3, 0.3, 1}, 0, 3, 4)));
}

// Two faces of the Loop-subdivided blade's thin trailing edge (x and z agree to 1e-7 along a
// strip 0.23 long) that share one corner: the edge test along the strip finds a near-touch
// (relative 1e-12), but the far corners of one lie strictly on one side of the other's plane,
// so the two touch at the shared corner only. Checked here in long double, apart from the test.
TEST(TrianglesIntersect, OneSideOfTheOthersPlaneIsApartEvenWhenNearlyTouching) {
  const Triangle a = Tri({3.9452977180480957, 33.119499206542969, 1.8070428371429443},
                         {3.9498472213745117, 32.885704040527344, 1.8047683238983154},
                         {3.9498469829559326, 33.119503021240234, 1.804768443107605}, 0, 1, 2);
  const Triangle b = Tri({3.9498472213745117, 33.353427886962891, 1.8047683238983154},
                         {3.9452977180480957, 33.353427886962891, 1.8070428371429443},
                         {3.9452977180480957, 33.119499206542969, 1.8070428371429443}, 3, 4, 0);
  // The side of q of t's plane, in long double: its sign and its size against the plane test's
  // relative margin.
  auto side = [](const Triangle& t, const DVec3& q) {
    long double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
      const double DVec3::*axis = k == 0 ? &DVec3::x : k == 1 ? &DVec3::y : &DVec3::z;
      u[k] = (long double)(t.p[1].*axis) - t.p[0].*axis;
      v[k] = (long double)(t.p[2].*axis) - t.p[0].*axis;
      w[k] = (long double)(q.*axis) - t.p[0].*axis;
    }
    const long double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                              u[0] * v[1] - u[1] * v[0]};
    const long double dot = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
    auto norm = [](const long double* x) { return sqrtl(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); };
    return dot / (norm(u) * norm(v) * norm(w));
  };
  // a's corners 1 and 2 (beyond the shared corner 0) of b's plane, or b's 0 and 1 of a's.
  const long double a1 = side(b, a.p[1]), a2 = side(b, a.p[2]);
  const long double b0 = side(a, b.p[0]), b1 = side(a, b.p[1]);
  const bool a_apart = a1 * a2 > 0 && fabsl(a1) > 1e-12L && fabsl(a2) > 1e-12L;
  const bool b_apart = b0 * b1 > 0 && fabsl(b0) > 1e-12L && fabsl(b1) > 1e-12L;
  ASSERT_TRUE(a_apart || b_apart) << a1 << " " << a2 << " " << b0 << " " << b1;
  EXPECT_FALSE(TrianglesIntersect(a, b));
  EXPECT_FALSE(TrianglesIntersect(b, a));
}

TEST(FaceGrid, OverlappingBoxesCannotBothBeHeld) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(testing::FlatGrid(8));  // the square [0, 8]^2
  ASSERT_TRUE(mesh.ok());
  FaceGrid grid(*mesh);
  const FaceGrid::Box a{{0.8, 0.8, 0}, {2.4, 2.4, 0}}, b{{2, 2, 0}, {4, 4, 0}};
  const FaceGrid::Box far{{6.6, 6.6, 0}, {7.4, 7.4, 0}};
  std::vector<uint32_t> held_a, held_b, held_far;
  ASSERT_EQ(grid.Acquire(a, &held_a), FaceGrid::Hold::kHeld);
  EXPECT_EQ(grid.Acquire(b, &held_b), FaceGrid::Hold::kBusy);
  EXPECT_TRUE(held_b.empty());  // nothing stays locked after a conflict
  EXPECT_EQ(grid.Acquire(far, &held_far), FaceGrid::Hold::kHeld);
  // The faces listed in held cells are the mesh's faces there.
  size_t listed = 0;
  grid.ForEachFace(a, held_a, [&](uint32_t) { return ++listed, true; });
  EXPECT_GT(listed, 0u);
  grid.Release(&held_a);
  EXPECT_EQ(grid.Acquire(b, &held_b), FaceGrid::Hold::kHeld);
  grid.Release(&held_b);
  grid.Release(&held_far);
}

// A deterministic round never finds the table of cells full: told how many new cells its boxes
// may claim, BeginRound grows the table first (else the 1024-slot table of this small mesh
// refuses the 769th new cell, and which collapse meets that would depend on timing).
TEST(FaceGrid, RoundGrowsTheTableForItsNewCells) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(testing::FlatGrid(8));
  ASSERT_TRUE(mesh.ok());
  FaceGrid grid(*mesh);
  const double c = grid.cell_size();
  std::vector<FaceGrid::Box> boxes;  // one cell each, none of them holding a face
  for (int k = 0; k < 3000; ++k) {
    const double x = (k % 60 + 0.25) * c, y = (k / 60 + 0.25) * c, z = 100 * c;
    boxes.push_back({{x, y, z}, {x + 0.5 * c, y + 0.5 * c, z + 0.5 * c}});
  }
  uint64_t new_cells = 0;
  for (const FaceGrid::Box& b : boxes) new_cells += grid.CellsOf(b);
  EXPECT_EQ(new_cells, boxes.size());
  grid.BeginRound(*mesh, new_cells);
  std::vector<uint32_t> held;
  for (const FaceGrid::Box& b : boxes) ASSERT_EQ(grid.Acquire(b, &held), FaceGrid::Hold::kHeld);
  grid.Release(&held);
  grid.EndRound(*mesh);
  // The faces are all still listed.
  std::vector<uint32_t> all;
  const FaceGrid::Box square{{0, 0, 0}, {8, 8, 0}};
  ASSERT_EQ(grid.Acquire(square, &all), FaceGrid::Hold::kHeld);
  std::set<uint32_t> listed;
  grid.ForEachFace(square, all, [&](uint32_t f) { return listed.insert(f), true; });
  EXPECT_EQ(listed.size(), mesh->CountLiveFaces());
  grid.Release(&all);
}

// The faces listed in the cells of `tile`, sorted (a cell's order is the contexts').
std::vector<uint32_t> ListedIn(FaceGrid& grid, const FaceGrid::Box& tile) {
  std::vector<uint32_t> held, listed;
  EXPECT_EQ(grid.Acquire(tile, &held), FaceGrid::Hold::kHeld);
  grid.ForEachFace(tile, held, [&](uint32_t f) { return listed.push_back(f), true; });
  grid.Release(&held);
  std::sort(listed.begin(), listed.end());
  return listed;
}

TEST(FaceGrid, IndexedOnAPoolTheSameAsAlone) {
  // 131,072 faces: three chunks of the build, on two contexts.
  const RawMesh raw = testing::FlatGrid(256);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  WorkerPool pool(2);
  FaceGrid alone(*mesh), pooled(*mesh, {}, &pool);
  EXPECT_EQ(alone.cell_size(), pooled.cell_size());
  EXPECT_EQ(alone.magnitude(), pooled.magnitude());
  float extent = 0;
  for (float x : raw.positions) extent = std::max(extent, x);
  const double c = alone.cell_size();
  size_t listings = 0;
  for (double x = -c; x < extent + c; x += 4 * c)
    for (double y = -c; y < extent + c; y += 4 * c) {
      const FaceGrid::Box tile{{x, y, -c}, {x + 3.9 * c, y + 3.9 * c, c}};
      const std::vector<uint32_t> listed = ListedIn(alone, tile);
      EXPECT_EQ(listed, ListedIn(pooled, tile)) << "tile at " << x << ", " << y;
      listings += listed.size();
    }
  EXPECT_GE(listings, raw.num_faces());
}

// A round's moves commute (a face moves at most once a round): shared by a pool's contexts, each
// cell under its lock, they leave every cell listing the same faces as one context applying them.
TEST(FaceGrid, RoundMovesSharedOnAPoolListTheSameAsAlone) {
  const RawMesh raw = testing::FlatGrid(96);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  WorkerPool pool(3);
  FaceGrid alone(*mesh), shared(*mesh);
  const double c = alone.cell_size();
  for (FaceGrid* grid : {&alone, &shared}) {
    grid->BeginRound(*mesh, 0);
    // Every third face slides over a cell and a half, every third is removed.
    for (uint32_t f = 0; f < mesh->face_capacity(); ++f) {
      const Triangle t = grid->FaceTriangle(f);
      const FaceGrid::Box before = FaceGrid::BoxOf(t.p, 3);
      const FaceGrid::Box after{before.lo + DVec3{1.5 * c, 0.25 * c, 0},
                                before.hi + DVec3{1.5 * c, 0.25 * c, 0}};
      if (f % 3 == 0) grid->Move(f, before, &after);
      if (f % 3 == 1) grid->Move(f, before, nullptr);
    }
  }
  alone.EndRound(*mesh);
  const size_t moves = shared.MovesOfRound();
  EXPECT_EQ(moves, 2 * mesh->face_capacity() / 3);
  WorkShares shares(pool.size());
  shares.Reset(moves);
  pool.Run([&](int k) {
    size_t begin, end;
    while (shares.Next(k, 16, &begin, &end)) shared.ApplyMoves(begin, end, /*shared=*/true);
  });
  shared.FinishRound(*mesh);
  size_t listings = 0;
  for (double x = -2 * c; x < 100; x += 4 * c)
    for (double y = -2 * c; y < 100; y += 4 * c) {
      const FaceGrid::Box tile{{x, y, -c}, {x + 3.9 * c, y + 3.9 * c, c}};
      const std::vector<uint32_t> listed = ListedIn(alone, tile);
      EXPECT_EQ(listed, ListedIn(shared, tile)) << "tile at " << x << ", " << y;
      for (uint32_t f : listed) EXPECT_NE(f % 3, 1u) << "removed face " << f << " listed";
      listings += listed.size();
    }
  EXPECT_GE(listings, mesh->face_capacity() / 3 * 2);
}

// Pairs of faces of a soup that intersect, by brute force.
size_t IntersectingPairs(const RawMesh& m) {
  std::vector<Triangle> t(m.num_faces());
  for (size_t f = 0; f < t.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[3 * f + k];
      t[f].id[k] = v;
      t[f].p[k] = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
    }
  size_t pairs = 0;
  for (size_t a = 0; a < t.size(); ++a)
    for (size_t b = a + 1; b < t.size(); ++b) pairs += TrianglesIntersect(t[a], t[b]);
  return pairs;
}

// A thin torus (tube radius 0.15 around a ring of radius 1) simplified with a tolerance far
// larger than its tube and with the normal and feature rules out of the way: without the rule
// the output intersects itself; with it, not, at 1 and 2 threads and on the cell back end.
TEST(SelfIntersectionRule, ThinPartStaysFreeOfIntersections) {
  const RawMesh input = testing::MakeTorus(40, 12, 1.0, 0.15);
  ASSERT_EQ(IntersectingPairs(input), 0u);
  SimplifyOptions options;
  options.tolerance_relative = 0.3;
  options.max_volume_change = 0;
  options.min_angle_deg = 0;
  options.max_normal_deviation_deg = 180;
  options.feature_angle_deg = 180;
  options.threads = 1;
  options.allow_self_intersections = true;
  EXPECT_GT(IntersectingPairs(testing::SimplifyChecked(input, options).output), 0u);
  options.allow_self_intersections = false;
  for (int threads : {1, 2}) {
    for (Backend backend : {Backend::kNative, Backend::kCell}) {
      options.threads = threads;
      options.backend = backend;
      options.cell.spes = threads;
      const testing::SimplifyRun run = testing::SimplifyChecked(input, options);
      EXPECT_LT(run.output.num_vertices(), input.num_vertices() / 2);
      EXPECT_EQ(IntersectingPairs(run.output), 0u) << threads << " contexts";
    }
  }
}

}  // namespace
}  // namespace femsimp
