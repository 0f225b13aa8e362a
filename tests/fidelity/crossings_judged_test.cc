// The crossings an output is reported with (engine/crossings.h), judged by CGAL's exact
// predicates (tests/judge/soup_intersections.cc): every reported pair must cross, and on soups
// in general position, where no pair touches without crossing, the counts must be equal.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>

#include "engine/crossings.h"
#include "tests/judge/judge.h"

namespace femsimp {
namespace {

// `faces` triangles on a pool of `points` random points, each triangle's corners drawn within
// `reach` of its first, so that faces share corners and edges as a mesh's do, and cross where
// they happen to. No two faces have the same three corners (a duplicate facet is repair's to
// remove, and CGAL counts it as meeting its twin).
RawMesh RandomSoup(uint32_t seed, size_t points, size_t faces, float reach) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  RawMesh m;
  for (size_t i = 0; i < 3 * points; ++i) m.positions.push_back(unit(random));
  std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(points) - 1);
  const auto near = [&](uint32_t a, uint32_t b) {
    for (int k = 0; k < 3; ++k)
      if (std::abs(m.positions[3 * a + k] - m.positions[3 * b + k]) > reach) return false;
    return true;
  };
  std::set<std::array<uint32_t, 3>> seen;
  while (m.num_faces() < faces) {
    const uint32_t a = pick(random);
    uint32_t b = pick(random), c = pick(random);
    for (int tries = 0; tries < 1000 && (b == a || !near(a, b)); ++tries) b = pick(random);
    for (int tries = 0; tries < 1000 && (c == a || c == b || !near(a, c)); ++tries)
      c = pick(random);
    if (b == a || c == a || c == b) continue;
    std::array<uint32_t, 3> corners{a, b, c};
    std::sort(corners.begin(), corners.end());
    if (!seen.insert(corners).second) continue;
    m.triangles.insert(m.triangles.end(), {a, b, c});
  }
  return m;
}

TEST(CrossingsJudged, CountsAgreeWithCgalInGeneralPosition) {
  uint64_t total = 0;
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    const float reach = seed % 2 == 0 ? 1.0f : 0.15f;  // faces across the cube, or small ones
    const RawMesh soup = RandomSoup(seed, 400, 500, reach);
    const SoupCrossings found = FindCrossings(soup);
    EXPECT_EQ(found.pairs, judge::SoupSelfIntersectingPairs(soup)) << "seed " << seed;
    total += found.pairs;
  }
  EXPECT_GT(total, 1000u);  // the soups do cross, often
}

// On a coarse lattice faces touch, lie in common planes and pass through each other's corners and
// edges: the report may leave out what is within rounding of touching, never call a pair that
// CGAL finds apart.
TEST(CrossingsJudged, OnALatticeEveryReportedPairCrossesByCgal) {
  RawMesh soup = RandomSoup(11, 64, 200, 1.0f);
  for (float& x : soup.positions) x = std::floor(4 * x);  // the points of a 4 x 4 x 4 lattice
  // Faces whose corners now lie on a line have no plane to cross, and the judge leaves them out
  // (small integers: the cross product is exact).
  RawMesh faces_with_a_plane = soup;
  faces_with_a_plane.triangles.clear();
  for (size_t f = 0; f < soup.num_faces(); ++f) {
    double p[3][3];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) p[k][a] = soup.positions[3 * soup.triangles[3 * f + k] + a];
    const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    if (u[1] * v[2] - u[2] * v[1] == 0 && u[2] * v[0] - u[0] * v[2] == 0 &&
        u[0] * v[1] - u[1] * v[0] == 0)
      continue;
    faces_with_a_plane.triangles.insert(faces_with_a_plane.triangles.end(),
                                        soup.triangles.begin() + 3 * f,
                                        soup.triangles.begin() + 3 * f + 3);
  }
  soup = faces_with_a_plane;
  ASSERT_GT(soup.num_faces(), 100u);
  uint64_t reported = 0, touching_or_folded = 0;
  for (uint32_t a = 0; a < soup.num_faces(); ++a)
    for (uint32_t b = a + 1; b < soup.num_faces(); ++b) {
      RawMesh pair;
      pair.positions = soup.positions;
      for (const uint32_t f : {a, b})
        pair.triangles.insert(pair.triangles.end(), soup.triangles.begin() + 3 * f,
                              soup.triangles.begin() + 3 * f + 3);
      const bool cgal = judge::SoupSelfIntersectingPairs(pair) > 0;
      const bool ours = FindCrossings(pair).pairs > 0;
      EXPECT_TRUE(cgal || !ours) << "faces " << a << " and " << b;
      reported += ours;
      touching_or_folded += cgal && !ours;
    }
  EXPECT_EQ(FindCrossings(soup).pairs, reported);
  EXPECT_GT(reported, 0u);
  EXPECT_GT(touching_or_folded, 0u);  // the lattice does make contacts the report leaves out
}

TEST(CrossingsJudged, TheFirstPairReportedCrosses) {
  const RawMesh soup = RandomSoup(7, 400, 500, 0.15f);
  const SoupCrossings found = FindCrossings(soup);
  ASSERT_GT(found.pairs, 0u);
  RawMesh pair;
  for (const uint32_t f : {found.face_a, found.face_b})
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = soup.triangles[3 * f + k];
      pair.triangles.push_back(static_cast<uint32_t>(pair.num_vertices()));
      pair.positions.insert(pair.positions.end(), {soup.positions[3 * v], soup.positions[3 * v + 1],
                                                   soup.positions[3 * v + 2]});
    }
  EXPECT_EQ(judge::SoupSelfIntersectingPairs(pair), 1u);
}

}  // namespace
}  // namespace femsimp
