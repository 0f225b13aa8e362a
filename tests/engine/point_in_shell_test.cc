// PointInShell (engine/point_in_shell.h): the winding number by a ray, against the solid angle's
// at random points, and at points whose ray runs exactly through
// edges and vertices of the facets, where a crossing must still count once.
#include "engine/point_in_shell.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

// The solid angle the facets subtend at p over 4π (Van Oosterom and Strackee), rounded.
int SolidAngleWinding(const RawMesh& m, const DVec3& p) {
  double w = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    DVec3 c[3];
    for (int k = 0; k < 3; ++k) {
      const float* q = &m.positions[3 * size_t(m.triangles[3 * f + k])];
      c[k] = {q[0], q[1], q[2]};
    }
    const DVec3 u = c[0] - p, v = c[1] - p, t = c[2] - p;
    const double lu = Norm(u), lv = Norm(v), lt = Norm(t);
    w += std::atan2(Dot(u, Cross(v, t)),
                    lu * lv * lt + Dot(u, v) * lt + Dot(u, t) * lv + Dot(v, t) * lu) /
         (2 * std::numbers::pi);
  }
  return int(std::lround(w));
}

TEST(PointInShell, RaysThroughEdgesAndVerticesCountOnce) {
  // A box of 4 x 4 x 4 squares per side: every point at a quarter in y and z sends its ray
  // through vertices, every point at an eighth through the squares' diagonals or sides.
  const RawMesh box = testing::MakeBox({1, 1, 1}, {4, 4, 4});
  const PointInShell test(box.positions.data(), box.triangles);
  for (int i = -2; i <= 10; ++i)
    for (int j = -2; j <= 10; ++j)
      for (const double x : {-0.5, 0.3, 0.55, 1.5}) {
        const DVec3 p{x, i / 8.0, j / 8.0};
        // On a side of the box (y or z at 0 or 1) the point counts as moved by (ε, ε²).
        const bool inside = x > 0 && x < 1 && i >= 0 && i < 8 && j >= 0 && j < 8;
        EXPECT_EQ(test.Winding(p), inside ? 1 : 0) << p.x << " " << p.y << " " << p.z;
      }
  RawMesh inward = box;
  for (size_t f = 0; f < inward.num_faces(); ++f)
    std::swap(inward.triangles[3 * f + 1], inward.triangles[3 * f + 2]);
  EXPECT_EQ(PointInShell(inward.positions.data(), inward.triangles).Winding({0.5, 0.5, 0.5}), -1);
}

TEST(PointInShell, SameAsTheSolidAngleOnATorus) {
  const RawMesh torus = testing::MakeTorus(40, 24);
  const PointInShell test(torus.positions.data(), torus.triangles);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> at(-4, 4);
  int inside = 0;
  for (int n = 0; n < 2000; ++n) {
    const DVec3 p{at(rng), at(rng), at(rng) / 2};
    const int w = test.Winding(p);
    EXPECT_EQ(w, SolidAngleWinding(torus, p)) << p.x << " " << p.y << " " << p.z;
    inside += w != 0;
  }
  EXPECT_GT(inside, 50);
}

}  // namespace
}  // namespace femsimp
