#include "engine/planar_retile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "engine/triangle_intersection.h"

namespace femsimp {
namespace {

// A closed fan around `centre` through `ring` (counter-clockwise or not, as given).
Ring FanOf(const Vec3& centre, const std::vector<Vec3>& ring) {
  Ring fan;
  fan.center = 0;
  fan.center_pos = centre;
  fan.faces = static_cast<int>(ring.size());
  for (int i = 0; i < fan.faces; ++i) {
    fan.nbr[i] = static_cast<uint32_t>(i + 1);
    fan.pos[i] = ring[i];
  }
  return fan;
}

// Points at these angles (degrees) and radii around (0, 0) in the plane z = 5.
std::vector<Vec3> RingAt(const std::vector<double>& degrees, const std::vector<double>& radii) {
  std::vector<Vec3> ring;
  for (size_t i = 0; i < degrees.size(); ++i) {
    const double a = degrees[i] * std::numbers::pi / 180.0;
    ring.push_back({static_cast<float>(radii[i] * std::cos(a)),
                    static_cast<float>(radii[i] * std::sin(a)), 5.0f});
  }
  return ring;
}

TEST(RetilesTheFanInItsPlane, ConvexRingInEveryDirectionAndEitherOrientation) {
  std::vector<Vec3> ring = RingAt({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1});
  const Vec3 centre{0, 0, 5};
  for (int target = 0; target < 6; ++target)
    EXPECT_TRUE(RetilesTheFanInItsPlane(FanOf(centre, ring), target)) << target;
  // Work for the cell back end's cycle model: 9 coordinate compares (x fails at once, y at the
  // second point, z holds for all six), 6 old and 4 new orientations.
  int tests = 0;
  EXPECT_TRUE(RetilesTheFanInItsPlane(FanOf(centre, ring), 0, &tests));
  EXPECT_EQ(tests, 19);
  std::reverse(ring.begin(), ring.end());
  for (int target = 0; target < 6; ++target)
    EXPECT_TRUE(RetilesTheFanInItsPlane(FanOf(centre, ring), target)) << target;
}

TEST(RetilesTheFanInItsPlane, OnlyInAnAxisPlaneExactly) {
  std::vector<Vec3> ring = RingAt({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1});
  ring[3].z = std::nextafter(5.0f, 6.0f);  // one ulp off the plane
  EXPECT_FALSE(RetilesTheFanInItsPlane(FanOf({0, 0, 5}, ring), 0));
  // The same hexagon in x = 2 (coordinates y, z) and in y = -7.5.
  std::vector<Vec3> in_x, in_y;
  for (const Vec3& p : RingAt({0, 60, 120, 180, 240, 300}, {1, 1, 1, 1, 1, 1})) {
    in_x.push_back({2, p.x, p.y});
    in_y.push_back({p.y, -7.5f, p.x});
  }
  EXPECT_TRUE(RetilesTheFanInItsPlane(FanOf({2, 0, 0}, in_x), 1));
  EXPECT_TRUE(RetilesTheFanInItsPlane(FanOf({0, -7.5f, 0}, in_y), 4));
}

TEST(RetilesTheFanInItsPlane, ABoundaryFanIsNotShown) {
  Ring fan = FanOf({0, 0, 5}, RingAt({0, 60, 120, 180}, {1, 1, 1, 1}));
  fan.faces = 3;
  fan.boundary = true;
  EXPECT_FALSE(RetilesTheFanInItsPlane(fan, 0));
}

TEST(RetilesTheFanInItsPlane, ADentedRingOnlyTowardsAPointThatSeesItAll) {
  // A dent at B = (0.3, 0.3): D = (-2, 0) sees the whole ring, A = (2, 0) does not see C past it
  // (the new triangle A, B, C turns the other way).
  const std::vector<Vec3> ring = {{2, 0, 5}, {0.3f, 0.3f, 5}, {0, 2, 5}, {-2, 0, 5}, {0, -2, 5}};
  const Ring fan = FanOf({0, 0, 5}, ring);
  EXPECT_TRUE(RetilesTheFanInItsPlane(fan, 3));
  EXPECT_FALSE(RetilesTheFanInItsPlane(fan, 0));
}

TEST(RetilesTheFanInItsPlane, AFanWindingTwiceIsNotShown) {
  // Steps of 144 degrees: every triangle turns the same way, and the ring goes round twice.
  const Ring fan = FanOf({0, 0, 5}, RingAt({0, 144, 288, 72, 216}, {1, 1, 1, 1, 1}));
  for (int target = 0; target < 5; ++target) EXPECT_FALSE(RetilesTheFanInItsPlane(fan, target));
  // Twice round too, and every new triangle towards ring point 0 turns the fan's way: only the
  // winding number tells (the new triangles would cover parts of the ring's inside twice).
  const Ring twice = FanOf({0, 0, 5}, {{0.788f, 0, 5},
                                       {-0.962f, 1.236f, 5},
                                       {1.573f, -2.196f, 5},
                                       {1.061f, -0.736f, 5},
                                       {1.898f, -0.112f, 5},
                                       {-2.273f, 0.587f, 5},
                                       {0.1f, -2.146f, 5}});
  EXPECT_FALSE(RetilesTheFanInItsPlane(twice, 0));
}

TEST(RetilesTheFanInItsPlane, AFlatOrDegenerateTriangleIsNotShown) {
  // V on the segment between two ring points: a fan face of no area.
  const std::vector<Vec3> ring = {{1, 0, 5}, {0, 1, 5}, {-1, 0, 5}, {0, -1, 5}};
  EXPECT_FALSE(RetilesTheFanInItsPlane(FanOf({0.5f, 0.5f, 5}, ring), 2));
  // Collapsing onto a ring point whose new triangle would be flat (three ring points in line).
  const std::vector<Vec3> lined = {{1, 0, 5}, {0, 1, 5}, {-1, 2, 5}, {-1, -1, 5}};
  EXPECT_FALSE(RetilesTheFanInItsPlane(FanOf({-0.2f, 0.1f, 5}, lined), 0));
  EXPECT_TRUE(RetilesTheFanInItsPlane(FanOf({0, 0, 5}, ring), 0));
}

// A jittered triangulated grid in the plane x = 3.25; the fan of every interior vertex and every
// direction the predicate accepts: its new triangles meet no face outside the fan and none of
// each other, by the self-intersection rule's own test, and cover the fan's area.
TEST(RetilesTheFanInItsPlane, WhereItHoldsTheRulesTestFindsNothingInAJitteredPlate) {
  constexpr int kN = 14;
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> jitter(-0.33, 0.33);
  std::vector<DVec3> points(kN * kN);
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j)
      points[i * kN + j] = {3.25, double(float(10.0 + i + jitter(rng))),
                            double(float(-4.0 + j + jitter(rng)))};
  const auto id = [](int i, int j) { return static_cast<uint32_t>(i * kN + j); };
  std::vector<Triangle> faces;
  for (int i = 0; i + 1 < kN; ++i)
    for (int j = 0; j + 1 < kN; ++j) {
      for (const auto& f : {std::array<uint32_t, 3>{id(i, j), id(i + 1, j), id(i + 1, j + 1)},
                            std::array<uint32_t, 3>{id(i, j), id(i + 1, j + 1), id(i, j + 1)}})
        faces.push_back({{points[f[0]], points[f[1]], points[f[2]]}, {f[0], f[1], f[2]}});
    }
  const int steps[6][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 0}, {-1, -1}, {0, -1}};
  const auto area = [](const Triangle& t) {
    return 0.5 * Norm(Cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
  };
  int shown = 0, not_shown = 0;
  for (int i = 1; i + 1 < kN; ++i)
    for (int j = 1; j + 1 < kN; ++j) {
      std::vector<Vec3> ring;
      std::vector<uint32_t> ring_id;
      for (const auto& s : steps) {
        const DVec3& p = points[id(i + s[0], j + s[1])];
        ring.push_back({float(p.x), float(p.y), float(p.z)});
        ring_id.push_back(id(i + s[0], j + s[1]));
      }
      const DVec3& c = points[id(i, j)];
      const Ring fan = FanOf({float(c.x), float(c.y), float(c.z)}, ring);
      double fan_area = 0;
      for (int f = 0; f < 6; ++f)
        fan_area += area({{c, points[ring_id[f]], points[ring_id[(f + 1) % 6]]},
                          {id(i, j), ring_id[f], ring_id[(f + 1) % 6]}});
      for (int target = 0; target < 6; ++target) {
        if (!RetilesTheFanInItsPlane(fan, target)) {
          ++not_shown;
          continue;
        }
        ++shown;
        std::vector<Triangle> fresh;
        double fresh_area = 0;
        for (int f = 0; f < 6; ++f) {
          const int g = (f + 1) % 6;
          if (f == target || g == target) continue;
          fresh.push_back({{points[ring_id[target]], points[ring_id[f]], points[ring_id[g]]},
                           {ring_id[target], ring_id[f], ring_id[g]}});
          fresh_area += area(fresh.back());
        }
        EXPECT_NEAR(fresh_area, fan_area, 1e-9 * fan_area);
        for (size_t a = 0; a < fresh.size(); ++a) {
          for (size_t b = a + 1; b < fresh.size(); ++b)
            EXPECT_FALSE(TrianglesIntersect(fresh[a], fresh[b]));
          for (const Triangle& other : faces) {
            bool in_fan = false;
            for (uint32_t k : other.id) in_fan = in_fan || k == id(i, j);
            if (!in_fan) {
              EXPECT_FALSE(TrianglesIntersect(fresh[a], other)) << i << " " << j;
            }
          }
        }
      }
    }
  // Both answers occur: the jitter dents some rings and turns some triangles over.
  EXPECT_GT(shown, 500);
  EXPECT_GT(not_shown, 20);
}

}  // namespace
}  // namespace femsimp
