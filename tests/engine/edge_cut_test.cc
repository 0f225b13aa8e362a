// The pair certificate of the measured check (engine/edge_cut.h): a triangle cut between two
// triangles across an edge, each side measured against its own.
#include "engine/edge_cut.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "engine/triangle_distance.h"

namespace femsimp {
namespace {

struct Pair {
  DVec3 a, b, c1, c2;
};

// CutWorst with every distance computed exactly.
double Worst(const Pair& p, const DVec3* c, double limit = 1e300) {
  const auto to_t = [&](const DVec3& q) { return SquaredDistanceToTriangle(q, p.a, p.b, p.c1); };
  const auto to_u = [&](const DVec3& q) { return SquaredDistanceToTriangle(q, p.b, p.a, p.c2); };
  return CutWorst(
      EdgeCut(p.a, p.b, p.c1, p.c2), c, [&](int q) { return to_t(c[q]); },
      [&](int q) { return to_u(c[q]); }, to_t, to_u, limit);
}

// The largest distance from a sample of the triangle's points to the nearer of t and u.
double SampledWorst(const Pair& p, const DVec3* c) {
  constexpr int kSteps = 120;
  double worst = 0;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j) {
      const DVec3 s =
          c[0] + (double(i) / kSteps) * (c[1] - c[0]) + (double(j) / kSteps) * (c[2] - c[0]);
      worst = std::max(worst, std::min(SquaredDistanceToTriangle(s, p.a, p.b, p.c1),
                                       SquaredDistanceToTriangle(s, p.b, p.a, p.c2)));
    }
  return worst;
}

// Never below the truth, on bent and flat pairs, folded ones included, and triangles across
// the edge, on one side, and far from both.
TEST(EdgeCut, NeverBelowTheDistanceToTheNearerTriangle) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  int straddling = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const double bend = 3.0 * u(rng);  // radians, up to nearly folded onto itself
    const Pair p{{0, 0, 0},
                 {1, 0, 0},
                 {0.2 + 0.5 * u(rng), 0.8 + 0.3 * u(rng), 0},
                 {0.5 + 0.5 * u(rng), -0.8 * std::cos(bend), 0.8 * std::sin(bend)}};
    const DVec3 c[3] = {{0.5 + 0.6 * u(rng), 0.6 * u(rng), 0.3 * u(rng)},
                        {0.5 + 0.6 * u(rng), 0.6 * u(rng), 0.3 * u(rng)},
                        {0.5 + 0.6 * u(rng), 0.6 * u(rng), 0.3 * u(rng)}};
    const EdgeCut cut(p.a, p.b, p.c1, p.c2);
    ASSERT_TRUE(cut.valid());
    const double sides[3] = {cut.Side(c[0]), cut.Side(c[1]), cut.Side(c[2])};
    straddling += std::min({sides[0], sides[1], sides[2]}) < 0 &&
                  std::max({sides[0], sides[1], sides[2]}) > 0;
    EXPECT_GE(Worst(p, c), SampledWorst(p, c) - 1e-12) << "trial " << trial;
  }
  EXPECT_GT(straddling, 100);
}

// A roof bent by far more than the tolerance: the chord of a triangle across its ridge dips
// under it, deepest where it meets the bisecting plane, and that is exactly what the cut
// measures there. (The hull of the two faces reaches 0.3 from them, the distance between the
// ridge and the segment joining the far corners: no use at any tolerance below that.)
TEST(EdgeCut, ExactForAChordAcrossABentRidge) {
  const double s = 0.3;  // the roof: z = -s |y|
  const Pair p{{0, 0, 0}, {1, 0, 0}, {0, 1, -s}, {1, -1, -s}};
  const DVec3 c[3] = {{0.2, 0.6, -0.6 * s}, {0.6, -0.5, -0.5 * s}, {0.9, 0, 0}};
  const double worst = Worst(p, c);
  const DVec3 under_ridge = c[0] + (0.6 / 1.1) * (c[1] - c[0]);  // the chord at y = 0
  EXPECT_NEAR(worst, SquaredDistanceToTriangle(under_ridge, p.a, p.b, p.c1), 1e-12);
  EXPECT_GE(worst, SampledWorst(p, c));
  EXPECT_LT(std::sqrt(worst), 0.2);
  // A limit below the answer stops it above the limit.
  EXPECT_GT(Worst(p, c, 0.5 * worst), 0.5 * worst);
}

// A flat convex quad holds every triangle inside it at no distance at all.
TEST(EdgeCut, AFlatQuadHoldsWhatLiesInIt) {
  const Pair p{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}};
  const DVec3 c[3] = {{0.1, 0.05, 0}, {0.95, 0.4, 0}, {0.3, 0.9, 0}};
  EXPECT_LT(Worst(p, c), 1e-30);
}

// No plane between a degenerate triangle and the other; a corner that is not a number is on
// neither side and refuses.
TEST(EdgeCut, DegenerateOrNotANumber) {
  EXPECT_FALSE(EdgeCut({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, -1, 0}).valid());
  EXPECT_FALSE(EdgeCut({0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0, -1, 0}).valid());
  const Pair p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const DVec3 c[3] = {{nan, 0, 0}, {0.5, 0.1, 0}, {0.5, -0.1, 0}};
  EXPECT_EQ(Worst(p, c), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace femsimp
