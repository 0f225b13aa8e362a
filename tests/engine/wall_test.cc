// The wall thickness under each face, and the wall rule that gives thin walls their own
// tolerance (engine/wall_thickness.h, engine/rules/wall_share.cc).
#include <algorithm>
#include <cmath>

#include "engine/mesh.h"
#include "engine/simplify.h"
#include "engine/wall_thickness.h"
#include "gtest/gtest.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::MakeBox;

RawMesh Reversed(RawMesh m) {
  for (size_t f = 0; f < m.num_faces(); ++f)
    std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]);
  return m;
}

TEST(WallThickness, OfAPlateAlongEachAxis) {
  const RawMesh plate = MakeBox({10, 8, 0.5}, {20, 16, 2});
  for (bool reversed : {false, true}) {
    SCOPED_TRACE(reversed ? "inside out" : "facing outward");
    absl::StatusOr<Mesh> mesh = Mesh::Build(reversed ? Reversed(plate) : plate);
    ASSERT_TRUE(mesh.ok()) << mesh.status();
    WorkerPool pool(2);
    const std::vector<float> t = WallThickness(*mesh, !reversed, &pool);
    ASSERT_EQ(t.size(), mesh->face_capacity());
    const HalfEdgeQ* h = mesh->halfedges();
    const VertexQ* v = mesh->vertices();
    for (uint32_t f = 0; f < mesh->face_capacity(); ++f) {
      // The axis the face is square to: its three corners share that coordinate.
      const VertexQ &a = v[h[3 * f].target], &b = v[h[3 * f + 1].target],
                    &c = v[h[3 * f + 2].target];
      const double expected = a.x == b.x && b.x == c.x   ? 10.0
                              : a.y == b.y && b.y == c.y ? 8.0
                                                         : 0.5;
      ASSERT_NEAR(t[f], expected, 1e-5) << "face " << f;
    }
  }
}

// The rays look no farther than `reach`: only the plate's 0.5 across is within 1.
TEST(WallThickness, NoWallBeyondTheReach) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(MakeBox({10, 8, 0.5}, {20, 16, 2}));
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  const std::vector<float> t = WallThickness(*mesh, true, nullptr, {}, 1.0);
  int thin = 0;
  for (float w : t) {
    if (w == kNoWall) continue;
    EXPECT_NEAR(w, 0.5, 1e-5);
    ++thin;
  }
  EXPECT_GT(thin, 0);
  EXPECT_LT(thin, static_cast<int>(t.size()));
}

TEST(WallThickness, NoWallWhereTheRaysLeave) {
  // An open sheet encloses nothing: no ray meets another face.
  absl::StatusOr<Mesh> mesh = Mesh::Build(testing::FlatGrid(4));
  ASSERT_TRUE(mesh.ok());
  for (float t : WallThickness(*mesh, true, nullptr)) EXPECT_EQ(t, kNoWall);
}

// Distance of p from the torus of radii 3 and r around the z axis.
double FromTorus(const float* p, double r) {
  const double ring = std::hypot(double(p[0]), double(p[1])) - 3.0;
  return std::fabs(std::hypot(ring, double(p[2])) - r);
}

// The largest distance, from the torus its face lies on, of the corners, edge midpoints and
// centroid of the output's faces near x = x0, over the tori of tube radius r_out and r_in (a
// shell; r_in 0: a solid torus). Chords: their midpoints sink below the surface.
double LargestDeviation(const RawMesh& out, float x0, double r_out, double r_in) {
  double worst = 0.0;
  for (size_t f = 0; f < out.num_faces(); ++f) {
    const float* c[3];
    for (int k = 0; k < 3; ++k) c[k] = &out.positions[3 * out.triangles[3 * f + k]];
    float centre[3];
    for (int a = 0; a < 3; ++a) centre[a] = (c[0][a] + c[1][a] + c[2][a]) / 3;
    if (std::fabs(centre[0] - x0) > 5.0f) continue;
    float q[3][3];  // the points relative to the torus's centre
    const auto at = [&](const float* p, float* o) {
      o[0] = p[0] - x0;
      o[1] = p[1];
      o[2] = p[2];
    };
    at(c[0], q[0]);
    // Which torus: the corner's tube radius.
    const double rho =
        std::hypot(std::hypot(double(q[0][0]), double(q[0][1])) - 3.0, double(q[0][2]));
    const double r = r_in > 0 && std::fabs(rho - r_in) < std::fabs(rho - r_out) ? r_in : r_out;
    for (int k = 0; k < 3; ++k) {
      float mid[3], pt[3];
      for (int a = 0; a < 3; ++a) mid[a] = (c[k][a] + c[(k + 1) % 3][a]) / 2;
      at(mid, pt);
      worst = std::max(worst, FromTorus(pt, r));
      at(c[k], pt);
      worst = std::max(worst, FromTorus(pt, r));
    }
    float pt[3];
    at(centre, pt);
    worst = std::max(worst, FromTorus(pt, r));
  }
  return worst;
}

// A thin-walled torus (a shell 0.1 thick) beside a solid one (2 across): with a tolerance of
// 0.05 and max_wall_share 0.2, the shell keeps within 0.02 of its surfaces and the solid torus
// uses the whole tolerance, with either deviation check (the mapped bound carries the faces'
// limits; the measured check holds each input triangle's pieces to its own).
class WallRule : public ::testing::TestWithParam<DeviationCheck> {};

TEST_P(WallRule, ThinWallsKeepTheirShareOfTheThickness) {
  const RawMesh input = testing::ShellBesideSolidTorus();
  SimplifyOptions o;
  o.tolerance = 0.05;
  o.tolerance_relative = 0.0;
  o.max_volume_change = 0.0;
  o.deviation_check = GetParam();
  o.threads = 2;
  const testing::SimplifyRun plain = testing::SimplifyChecked(input, o);
  o.max_wall_share = 0.2;
  const testing::SimplifyRun walls = testing::SimplifyChecked(input, o);

  // Without the rule both tori use the tolerance.
  EXPECT_GT(LargestDeviation(plain.output, 0.0f, 1.0, 0.9), 0.03);
  EXPECT_GT(LargestDeviation(plain.output, 10.0f, 1.0, 0.0), 0.025);
  EXPECT_EQ(plain.result.thinnest_wall, 0.0);
  // With it the shell keeps a fifth of its thickness; the solid torus is as free as before.
  // Measured against the input's triangles, the output may also lie as far from the analytic
  // tori as the input's own chords do (the mapped bound's slack hides that).
  const double shell_sag = LargestDeviation(input, 0.0f, 1.0, 0.9);
  const double solid_sag = LargestDeviation(input, 10.0f, 1.0, 0.0);
  ASSERT_LT(std::max(shell_sag, solid_sag), 0.006);  // 0.0052: small beside 0.02
  EXPECT_LE(LargestDeviation(walls.output, 0.0f, 1.0, 0.9), (0.02 + shell_sag) * (1 + 1e-5));
  EXPECT_GT(LargestDeviation(walls.output, 10.0f, 1.0, 0.0), 0.025);
  EXPECT_LE(LargestDeviation(walls.output, 10.0f, 1.0, 0.0), (0.05 + solid_sag) * (1 + 1e-5));
  EXPECT_GT(walls.result.output_vertices, plain.result.output_vertices);
  EXPECT_NEAR(walls.result.thinnest_wall, 0.1, 1e-3);
  // The shell's two tori hold 1.9 / 2.9 of the area (a torus's area grows with its tube radius).
  EXPECT_NEAR(walls.result.wall_limited_share, 1.9 / 2.9, 0.01);
  uint64_t refused = 0;
  for (const PassStats& pass : walls.result.passes)
    refused += pass.rejections[static_cast<int>(Reject::kWall)];
  // The measured check refuses what the limits refuse itself, as the tolerance's.
  if (GetParam() == DeviationCheck::kMapped)
    EXPECT_GT(refused, 0u);
  else
    EXPECT_EQ(refused, 0u);
}

INSTANTIATE_TEST_SUITE_P(Checks, WallRule,
                         ::testing::Values(DeviationCheck::kMapped, DeviationCheck::kMeasured),
                         [](const ::testing::TestParamInfo<DeviationCheck>& info) {
                           return info.param == DeviationCheck::kMapped ? "Mapped" : "Measured";
                         });

TEST(WallRuleOptions, RefusedWithoutATolerance) {
  SimplifyOptions o;
  o.max_wall_share = 0.2;
  for (DeviationCheck check : {DeviationCheck::kMapped, DeviationCheck::kMeasured}) {
    o.deviation_check = check;
    EXPECT_TRUE(ValidateOptions(o).ok());
  }
  o.tolerance = 0.0;
  o.tolerance_relative = 0.0;
  const absl::Status s = ValidateOptions(o);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("give a tolerance"), std::string::npos) << s;
}

}  // namespace
}  // namespace femsimp
