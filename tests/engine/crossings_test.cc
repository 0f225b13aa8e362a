#include "engine/crossings.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <utility>

#include "absl/strings/str_cat.h"
#include "engine/planar_overlap.h"
#include "engine/transversal_crossing.h"
#include "engine/worker_pool.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::Append;
using testing::FlatGrid;
using testing::MakeBox;
using testing::MakeTorus;
using testing::SingleTriangle;

Triangle TriangleOf(const RawMesh& m, size_t f) {
  Triangle t;
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = m.triangles[3 * f + k];
    t.p[k] = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
    t.id[k] = v;
  }
  return t;
}

// Every pair tested: what the grid must find, each pair once.
SoupCrossings BruteForce(const RawMesh& m) {
  SoupCrossings c;
  for (size_t a = 0; a < m.num_faces(); ++a)
    for (size_t b = a + 1; b < m.num_faces(); ++b)
      if (TransversalCrossing(TriangleOf(m, a), TriangleOf(m, b)) && c.pairs++ == 0) {
        c.face_a = static_cast<uint32_t>(a);
        c.face_b = static_cast<uint32_t>(b);
      }
  return c;
}

void ExpectAsBruteForce(const RawMesh& m) {
  const SoupCrossings grid = FindCrossings(m), all = BruteForce(m);
  EXPECT_EQ(grid.pairs, all.pairs);
  if (all.pairs == 0) return;
  EXPECT_EQ(std::pair(grid.face_a, grid.face_b), std::pair(all.face_a, all.face_b));
}

struct Scan {
  SoupCrossings found;
  CrossingPairLists lists;
};

Scan ScanOn(const RawMesh& m, WorkerPool* pool, size_t stop_after, bool crossings_only = false) {
  Scan s;
  s.found = FindCrossings(m, {.lists = &s.lists,
                              .crossings_only = crossings_only,
                              .stop_after = stop_after,
                              .pool = pool});
  return s;
}

void ExpectSameScan(const Scan& a, const Scan& b) {
  EXPECT_EQ(a.found.pairs, b.found.pairs);
  EXPECT_EQ(a.found.cut_short, b.found.cut_short);
  EXPECT_EQ(std::pair(a.found.face_a, a.found.face_b), std::pair(b.found.face_a, b.found.face_b));
  EXPECT_EQ(a.found.at, b.found.at);
  EXPECT_EQ(a.found.overlaps.pairs, b.found.overlaps.pairs);
  EXPECT_EQ(a.found.overlaps.area, b.found.overlaps.area);  // summed in the same order
  EXPECT_EQ(a.found.overlaps.at, b.found.overlaps.at);
  EXPECT_EQ(a.found.folds.pairs, b.found.folds.pairs);
  EXPECT_EQ(a.lists.crossing, b.lists.crossing);
  EXPECT_EQ(a.lists.overlapping, b.lists.overlapping);
  EXPECT_EQ(a.lists.folded, b.lists.folded);
}

// The cells are scanned in stretches on the pool's threads and joined in order: the counts, the
// first pairs, the overlaps' area and every list are those of one thread.
TEST(Crossings, ThreadsFindWhatOneThreadFinds) {
  RawMesh m = MakeTorus(240, 80);  // thousands of cells: many stretches
  Append(m, MakeTorus(240, 80), {0.6f, 0.4f, 0.3f});
  Append(m, MakeBox({4, 3, 1}, {40, 30, 10}), {-2.0f, -1.5f, -6.0f});  // a block on a plate
  Append(m, MakeBox({1.5, 1.25, 2}, {15, 12, 20}), {-1.25f, -1.0f, -5.0f});
  const Scan one = ScanOn(m, nullptr, SIZE_MAX);
  ASSERT_GT(one.found.pairs, 1000u);
  ASSERT_GT(one.found.overlaps.pairs, 100u);
  EXPECT_EQ(one.lists.crossing.size(), one.found.pairs);
  for (int threads : {2, 3}) {
    WorkerPool pool(threads);
    SCOPED_TRACE(threads);
    ExpectSameScan(ScanOn(m, &pool, SIZE_MAX), one);
    ExpectSameScan(ScanOn(m, &pool, SIZE_MAX, /*crossings_only=*/true),
                   ScanOn(m, nullptr, SIZE_MAX, /*crossings_only=*/true));
    const SoupCrossings counted = FindCrossings(m, {.pool = &pool});
    EXPECT_EQ(counted.pairs, one.found.pairs);
    EXPECT_EQ(counted.overlaps.area, one.found.overlaps.area);
  }
}

// A scan told to stop after so many crossing pairs ends at the same stretch of cells on any
// number of threads: a soup's report does not depend on the machine.
TEST(Crossings, AScanCutShortEndsAtTheSameStretchOnAnyThreads) {
  // Small facets all over a cube, crossing each other everywhere.
  const RawMesh soup = testing::RandomSoup(30000, 777, 0.05f);
  const Scan whole = ScanOn(soup, nullptr, SIZE_MAX);
  const Scan one = ScanOn(soup, nullptr, 1000, /*crossings_only=*/true);
  ASSERT_GT(whole.found.pairs, 5000u);
  EXPECT_TRUE(one.found.cut_short);
  EXPECT_FALSE(whole.found.cut_short);
  EXPECT_GT(one.found.pairs, 1000u);
  EXPECT_LT(one.found.pairs, whole.found.pairs / 2);
  EXPECT_EQ(one.lists.crossing.size(), one.found.pairs);
  for (int threads : {2, 3}) {
    WorkerPool pool(threads);
    SCOPED_TRACE(threads);
    ExpectSameScan(ScanOn(soup, &pool, 1000, /*crossings_only=*/true), one);
  }
}

TEST(Crossings, ClosedSurfacesHaveNone) {
  EXPECT_EQ(FindCrossings(MakeBox({1, 2, 3}, {3, 4, 5})).pairs, 0u);
  EXPECT_EQ(FindCrossings(MakeTorus(24, 12)).pairs, 0u);
  EXPECT_EQ(FindCrossings(SingleTriangle()).pairs, 0u);
  EXPECT_EQ(FindCrossings(RawMesh{}).pairs, 0u);
}

TEST(Crossings, TwoBoxesThroughEachOtherCrossAlongTheirSeam) {
  RawMesh m = MakeBox({1, 1, 1}, {4, 4, 4});
  const uint32_t first_faces = static_cast<uint32_t>(m.num_faces());
  Append(m, MakeBox({1, 1, 1}, {4, 4, 4}), {0.5f, 0.3f, 0.2f});
  const SoupCrossings c = FindCrossings(m);
  ASSERT_GT(c.pairs, 0u);
  EXPECT_LT(c.face_a, first_faces);
  EXPECT_GE(c.face_b, first_faces);
  const std::optional<DVec3> at =
      TransversalCrossing(TriangleOf(m, c.face_a), TriangleOf(m, c.face_b));
  ASSERT_TRUE(at.has_value());
  EXPECT_EQ(c.at, (std::array<double, 3>{at->x, at->y, at->z}));
  ExpectAsBruteForce(m);
}

TEST(Crossings, LargeFacesAmongSmallOnesAreEachCountedOnce) {
  // A fine torus pierced by a box of two triangles a side, as large as the torus: the cells
  // grow for the large faces, and each pair still counts once.
  RawMesh m = MakeTorus(40, 16);
  Append(m, MakeBox({9, 9, 0.5}, {1, 1, 1}), {-4.5f, -4.5f, -0.25f});
  ASSERT_GT(BruteForce(m).pairs, 0u);
  ExpectAsBruteForce(m);
}

TEST(Crossings, ContactsAndFoldsAreNotCrossings) {
  // Neighbours share an edge or a corner, and meet nowhere else.
  RawMesh grid = FlatGrid(6);
  EXPECT_EQ(FindCrossings(grid).pairs, 0u);
  // The same grid folded onto itself (a second copy of its faces on the same vertices, turned
  // over) meets the first along whole faces, within one plane: not a transversal crossing, and
  // not reported (engine/transversal_crossing.h says why).
  RawMesh folded = grid;
  for (size_t f = 0; f < grid.num_faces(); ++f)
    folded.triangles.insert(
        folded.triangles.end(),
        {grid.triangles[3 * f], grid.triangles[3 * f + 2], grid.triangles[3 * f + 1]});
  EXPECT_EQ(FindCrossings(folded).pairs, 0u);
  // Nor a fold: a face and its neighbour's copy run their edge the same way (misoriented, they
  // face no way).
  EXPECT_EQ(FindCrossings(folded).folds.pairs, 0u);
  // Shifted aside and tilted about a line across it, the copy crosses the grid along a line.
  RawMesh tilted = grid;
  const uint32_t base = static_cast<uint32_t>(grid.num_vertices());
  for (size_t v = 0; v < grid.num_vertices(); ++v) {
    const float x = grid.positions[3 * v], y = grid.positions[3 * v + 1];
    tilted.positions.insert(tilted.positions.end(),
                            {x + 0.031f, y + 0.017f, 0.3f * (x - 0.55f) + 0.013f * y});
  }
  for (uint32_t v : grid.triangles) tilted.triangles.push_back(base + v);
  EXPECT_GT(FindCrossings(tilted).pairs, 0u);
  ExpectAsBruteForce(tilted);
}

// The unit square in four facets, one of them turned over: (0, 1, 3) over the lower right half,
// (3, 4, 0) back over part of it to (0.7, 0.3), and the two facets from there to the upper left
// corner, together covering the square once, counted with orientation. The turned-over facet
// lies on each of its three neighbours: three folds, no crossing, no overlap.
TEST(Crossings, AFacetTurnedOverOntoItsNeighboursFolds) {
  RawMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0.7f, 0.3f, 0};
  m.triangles = {0, 1, 3, 3, 4, 0, 3, 2, 4, 2, 0, 4};
  const SoupCrossings c = FindCrossings(m);
  EXPECT_EQ(c.pairs, 0u);
  EXPECT_EQ(c.overlaps.pairs, 0u);
  EXPECT_EQ(c.folds.pairs, 3u);
  EXPECT_EQ(c.folds.face_a, 0u);
  EXPECT_EQ(c.folds.face_b, 1u);
  EXPECT_EQ(c.folds.at, (std::array<double, 3>{0.5, 0.5, 0}));
  EXPECT_EQ(DescribeFolds(c),
            "3 face pairs lie on each other in their plane, one of each turned over (the first: "
            "faces 0 and 1, along their common edge at (0.5, 0.5, 0))");
  // Unfolded (edge 0-3 flipped to 1-4), nothing is left.
  m.triangles = {0, 1, 4, 1, 3, 4, 3, 2, 4, 2, 0, 4};
  EXPECT_EQ(FindCrossings(m).folds.pairs, 0u);
  // Bent along the edge by 1 degree, the facets are a sharp edge, not a fold.
  RawMesh bent;
  bent.positions = {0, 0, 0, 1, 1, 0, 1, 0, 0};
  const double t = M_PI / 180;
  bent.positions.insert(bent.positions.end(),
                        {float(0.5 + 0.3 * std::cos(t)), float(0.5 - 0.3 * std::cos(t)),
                         float(0.3 * std::sqrt(2.0) * std::sin(t))});
  bent.triangles = {0, 1, 2, 1, 0, 3};
  EXPECT_EQ(FindCrossings(bent).folds.pairs, 0u);
}

// Two bodies exported apart that touch: a block standing on a plate, each triangulated on its own,
// so the block's bottom faces lie on the plate's top faces without sharing a vertex. tetgen
// refuses such a surface; FindCrossings counts the overlapping pairs apart from the crossings and
// measures the contact.
TEST(Crossings, BodiesTouchingWithoutSharedVerticesOverlapInTheirPlane) {
  RawMesh m = MakeBox({4, 3, 1}, {4, 3, 1});
  const uint32_t plate_faces = static_cast<uint32_t>(m.num_faces());
  Append(m, MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {0.75f, 0.5f, 1.0f});
  const SoupCrossings c = FindCrossings(m);
  EXPECT_EQ(c.pairs, 0u);
  ASSERT_GT(c.overlaps.pairs, 0u);
  EXPECT_NEAR(c.overlaps.area, 1.5 * 1.25, 1e-6);
  EXPECT_LT(c.overlaps.face_a, plate_faces);
  EXPECT_GE(c.overlaps.face_b, plate_faces);
  EXPECT_EQ(c.overlaps.at[2], 1.0);
  // Every pair tested: the same pairs, the first the same.
  uint64_t pairs = 0;
  std::pair<uint32_t, uint32_t> first;
  for (uint32_t a = 0; a < m.num_faces(); ++a)
    for (uint32_t b = a + 1; b < m.num_faces(); ++b)
      if (OverlapInPlane(TriangleOf(m, a), TriangleOf(m, b), 1e-6) && pairs++ == 0) first = {a, b};
  EXPECT_EQ(c.overlaps.pairs, pairs);
  EXPECT_EQ(std::pair(c.overlaps.face_a, c.overlaps.face_b), first);
  EXPECT_EQ(DescribeOverlaps(c).substr(0, 40),
            absl::StrCat(pairs, " face pairs overlap in their plane, over").substr(0, 40));
  // Against the plate's side, the contact 1.25 by the plate's height of 1.
  RawMesh beside = MakeBox({4, 3, 1}, {4, 3, 1});
  Append(beside, MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {4.0f, 0.5f, 0.0f});
  EXPECT_NEAR(FindCrossings(beside).overlaps.area, 1.25, 1e-6);
  // Lifted off the plate by a hundredth, or a hundredth away from its side: no contact.
  RawMesh apart = MakeBox({4, 3, 1}, {4, 3, 1});
  Append(apart, MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {0.75f, 0.5f, 1.01f});
  EXPECT_EQ(FindCrossings(apart).overlaps.pairs, 0u);
  RawMesh aside = MakeBox({4, 3, 1}, {4, 3, 1});
  Append(aside, MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {4.01f, 0.5f, 0.0f});
  EXPECT_EQ(FindCrossings(aside).overlaps.pairs, 0u);
  // Closed surfaces and a folded grid (its faces on shared edges) have none.
  EXPECT_EQ(FindCrossings(MakeTorus(24, 12)).overlaps.pairs, 0u);
}

// The same block on the plate, the pair turned about a skew axis and stored in floats, as a CAD
// export of a tilted assembly is: the block's bottom corners land a float spacing above or below
// the plate's top plane, so its side faces poke through the plate by that rounding. That is the
// contact, not a crossing; pushed into the plate by a hundredth, the block does cross it.
TEST(Crossings, TiltedContactRoundedToFloatIsNoCrossing) {
  const auto tilted = [](double lift) {
    RawMesh m = MakeBox({4, 3, 1}, {4, 3, 1});
    Append(m, MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {0.75f, 0.5f, float(1.0 + lift)});
    return testing::TurnedSkew(m);
  };
  const RawMesh touching = tilted(0.0);
  EXPECT_GT(BruteForce(touching).pairs, 0u);  // what rounding alone makes of the contact
  const SoupCrossings c = FindCrossings(touching);
  EXPECT_EQ(c.pairs, 0u) << DescribeCrossings(c);
  EXPECT_NEAR(c.overlaps.area, 1.5 * 1.25, 1e-4);
  const SoupCrossings pushed = FindCrossings(tilted(-0.01));
  EXPECT_GT(pushed.pairs, 0u);
  EXPECT_EQ(pushed.overlaps.pairs, 0u);
}

}  // namespace
}  // namespace femsimp
