#include "engine/fold.h"

#include <gtest/gtest.h>

#include <cmath>

namespace femsimp {
namespace {

constexpr double kTolerance = 1e-9;

// A point turned about the axis (1, 2, 3) / |.| by 0.7 rad and moved, then rounded to float as a
// file holds it: folds are judged off the axes and with rounded corners.
DVec3 Tilted(DVec3 p) {
  const DVec3 k = (1.0 / std::sqrt(14.0)) * DVec3{1, 2, 3};
  const double c = std::cos(0.7), s = std::sin(0.7);
  const DVec3 r = c * p + s * Cross(k, p) + ((1 - c) * Dot(k, p)) * k;
  return {double(float(r.x + 40)), double(float(r.y - 7)), double(float(r.z + 3))};
}

// The square's corners a = (0, 0), b = (1, 1) and c = (1, 0); d lies inside triangle (a, b, c),
// so (a, b, c) and (b, a, d) lie on each other, the second turned over.
const DVec3 kA{0, 0, 0}, kB{1, 1, 0}, kC{1, 0, 0}, kInside{0.7, 0.3, 0};

TEST(Fold, FacetsOnEachOtherFacingOppositeWaysFold) {
  EXPECT_TRUE(IsFold(kA, kB, kC, kInside, kTolerance));
  EXPECT_TRUE(IsFold(Tilted(kA), Tilted(kB), Tilted(kC), Tilted(kInside), 1e-6));
  // The same pair the right way round: d across the edge from c.
  EXPECT_FALSE(IsFold(kA, kB, kC, {0.3, 0.7, 0}, kTolerance));
}

TEST(Fold, ANarrowWedgeIsAnEdgeNotAFold) {
  // d turned up out of the plane about edge a-b by an opening angle: a sharp edge of a part at
  // 1 degree, a fold at 0.01 degrees (under kFoldSine).
  const DVec3 mid{0.5, 0.5, 0};
  const DVec3 out = DVec3{0.2, -0.2, 0};  // from the edge towards d, in the plane
  for (const auto& [degrees, folds] : {std::pair{1.0, false}, std::pair{0.01, true}}) {
    const double t = degrees * M_PI / 180;
    const DVec3 d = mid + DVec3{std::cos(t) * out.x, std::cos(t) * out.y, Norm(out) * std::sin(t)};
    EXPECT_EQ(IsFold(kA, kB, kC, d, kTolerance), folds) << degrees << " degrees";
  }
}

TEST(Fold, ZeroAreaFacetsNeverFold) {
  EXPECT_FALSE(IsFold(kA, kB, {0.5, 0.5, 0}, kInside, kTolerance));
  EXPECT_FALSE(IsFold(kA, kB, kC, {2, 2, 0}, kTolerance));
}

TEST(Fold, TheFlipUnfoldsWhereTheApexLiesInsideTheOtherFacet) {
  EXPECT_TRUE(FlipUnfolds(kA, kB, kC, kInside));
  EXPECT_TRUE(FlipUnfolds(Tilted(kA), Tilted(kB), Tilted(kC), Tilted(kInside)));
  // d beside c's facet, on its side of a-b: the two overlap only in part, and the other
  // diagonal would turn (b, c, d) over.
  EXPECT_TRUE(IsFold(kA, kB, kC, {1.5, 0.8, 0}, kTolerance));
  EXPECT_FALSE(FlipUnfolds(kA, kB, kC, {1.5, 0.8, 0}));
  // Two equal facets facing opposite ways (a double-sided sheet): nothing to face.
  EXPECT_TRUE(IsFold(kA, kB, kC, kC, kTolerance));
  EXPECT_FALSE(FlipUnfolds(kA, kB, kC, kC));
}

}  // namespace
}  // namespace femsimp
