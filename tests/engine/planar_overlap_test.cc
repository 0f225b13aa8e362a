#include "engine/planar_overlap.h"

#include <gtest/gtest.h>

#include <cmath>

namespace femsimp {
namespace {

constexpr double kTolerance = 1e-9;

Triangle Tri(DVec3 a, DVec3 b, DVec3 c, uint32_t first_id) {
  return {{a, b, c}, {first_id, first_id + 1, first_id + 2}};
}

// A point turned about the axis (1, 2, 3) / |.| by 0.7 rad and moved, then rounded to float as a
// file of another tool holds it.
DVec3 Tilted(DVec3 p) {
  const DVec3 k = (1.0 / std::sqrt(14.0)) * DVec3{1, 2, 3};
  const double c = std::cos(0.7), s = std::sin(0.7);
  const DVec3 r = c * p + s * Cross(k, p) + ((1 - c) * Dot(k, p)) * k;
  return {double(float(r.x + 40)), double(float(r.y - 7)), double(float(r.z + 3))};
}

TEST(PlanarOverlap, TheCommonPartOfTwoFacesInOnePlane) {
  // The lower left half of the unit square against the upper left half: the common part is the
  // triangle (0, 0), (0, 1), (0.5, 0.5), area 1/4, centroid (1/6, 1/2).
  const Triangle lower = Tri({0, 0, 2}, {1, 0, 2}, {0, 1, 2}, 0);
  const Triangle upper = Tri({0, 0, 2}, {1, 1, 2}, {0, 1, 2}, 3);
  const std::optional<PlanarOverlap> o = OverlapInPlane(lower, upper, kTolerance);
  ASSERT_TRUE(o.has_value());
  EXPECT_NEAR(o->area, 0.25, 1e-15);
  EXPECT_NEAR(o->at.x, 1.0 / 6, 1e-15);
  EXPECT_NEAR(o->at.y, 0.5, 1e-15);
  EXPECT_EQ(o->at.z, 2.0);
  // Either order, either winding (a body's face on another's faces the other way).
  const Triangle upper_turned = Tri({0, 0, 2}, {0, 1, 2}, {1, 1, 2}, 3);
  for (const auto& [a, b] :
       {std::pair(upper, lower), std::pair(lower, upper_turned), std::pair(upper_turned, lower)}) {
    const std::optional<PlanarOverlap> again = OverlapInPlane(a, b, kTolerance);
    ASSERT_TRUE(again.has_value());
    EXPECT_NEAR(again->area, 0.25, 1e-15);
  }
  // One inside the other: the smaller one's area.
  const Triangle small = Tri({0.1, 0.1, 2}, {0.3, 0.1, 2}, {0.1, 0.3, 2}, 6);
  EXPECT_NEAR(OverlapInPlane(lower, small, kTolerance)->area, 0.02, 1e-15);
  EXPECT_NEAR(OverlapInPlane(small, lower, kTolerance)->area, 0.02, 1e-15);
}

TEST(PlanarOverlap, AContactOnATiltedPlaneRoundedToFloat) {
  const Triangle a = Tri(Tilted({0, 0, 0}), Tilted({4, 0, 0}), Tilted({0, 4, 0}), 0);
  const Triangle b = Tri(Tilted({1, 1, 0}), Tilted({1, 2, 0}), Tilted({2, 1, 0}), 3);
  EXPECT_FALSE(OverlapInPlane(a, b, 0.0).has_value());  // rounding puts b off a's plane
  const std::optional<PlanarOverlap> o = OverlapInPlane(a, b, 1e-5);
  ASSERT_TRUE(o.has_value());
  EXPECT_NEAR(o->area, 0.5, 1e-5);
  const DVec3 centroid = Tilted({4.0 / 3, 4.0 / 3, 0});
  EXPECT_NEAR(Norm(o->at - centroid), 0.0, 1e-5);
}

TEST(PlanarOverlap, TouchingOrApartIsNoOverlap) {
  const Triangle a = Tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0);
  // Beside it along its long edge, and at a corner only.
  EXPECT_FALSE(OverlapInPlane(a, Tri({1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 3), kTolerance));
  EXPECT_FALSE(OverlapInPlane(a, Tri({1, 0, 0}, {2, 0, 0}, {2, 1, 0}, 3), kTolerance));
  // Along the same edge but over it by a float's rounding: no area to speak of.
  EXPECT_FALSE(OverlapInPlane(a, Tri({1, -1e-9, 0}, {1, 1, 0}, {-1e-9, 1, 0}, 3), kTolerance));
  // Above it (a wall's other side), across it, and degenerate.
  EXPECT_FALSE(OverlapInPlane(a, Tri({0, 0, 0.01}, {1, 0, 0.01}, {0, 1, 0.01}, 3), kTolerance));
  EXPECT_FALSE(OverlapInPlane(a, Tri({0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.5, 0.1, 0}, 3), kTolerance));
  EXPECT_FALSE(OverlapInPlane(a, Tri({0.1, 0.1, 0}, {0.2, 0.2, 0}, {0.3, 0.3, 0}, 3), kTolerance));
  EXPECT_FALSE(OverlapInPlane(Tri({0.1, 0.1, 0}, {0.2, 0.2, 0}, {0.3, 0.3, 0}, 3), a, kTolerance));
}

}  // namespace
}  // namespace femsimp
