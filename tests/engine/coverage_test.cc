// The measured deviation check (engine/coverage.h): pieces and their paths, the distance it
// trusts, one collapse judged by hand, and whole runs against the mapped bound.
#include "engine/coverage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/prepare.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

TEST(Piece, ChildAndParentAreInverse) {
  Piece p{7, 0};
  for (uint32_t step : {2u, 0u, 3u, 1u, 3u}) {
    const Piece child = p.Child(step);
    EXPECT_EQ(child.level(), p.level() + 1);
    EXPECT_EQ(child.triangle, 7u);
    EXPECT_EQ(child.Parent().path, p.path);
    p = child;
  }
  EXPECT_EQ(p.level(), 5);
}

double Area(const DVec3 t[3]) { return 0.5 * Norm(Cross(t[1] - t[0], t[2] - t[0])); }

// The four children of a piece tile it: their areas add up, and their corners lie in it.
TEST(Piece, ChildrenTileTheirParent) {
  const RawMesh raw = testing::SingleTriangle();
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  const Coverage coverage(*mesh, 0.1);
  const Piece parent = Piece{0, 0}.Child(1).Child(3);
  DVec3 p[3];
  coverage.Corners(parent, p);
  double sum = 0;
  for (uint32_t c = 0; c < 4; ++c) {
    DVec3 q[3];
    coverage.Corners(parent.Child(c), q);
    sum += Area(q);
    for (const DVec3& corner : q)
      EXPECT_LT(SquaredDistanceToTriangle(corner, p[0], p[1], p[2]), 1e-20);
  }
  EXPECT_NEAR(sum, Area(p), 1e-12);
}

// The distance the check trusts, against a dense sampling of the triangle: never below the
// true distance (the sampled minimum is above it by at most the sample spacing); and the same
// from TriangleDistance.
TEST(Coverage, DistanceToTriangleMatchesSampling) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    DVec3 t[3] = {{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    if (trial % 10 == 0) t[2] = t[0] + 0.5 * (t[1] - t[0]);  // degenerate: a segment
    if (trial % 10 == 1) t[1] = t[2] = t[0];                 // degenerate: a point
    const DVec3 q{2 * u(rng), 2 * u(rng), 2 * u(rng)};
    const double exact = std::sqrt(SquaredDistanceToTriangle(q, t[0], t[1], t[2]));
    constexpr int kSteps = 200;
    double sampled = 1e300, spacing = 0;
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double a = double(i) / kSteps, b = double(j) / kSteps;
        const DVec3 s = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]);
        sampled = std::min(sampled, Norm(q - s));
      }
    spacing = std::max({Norm(t[1] - t[0]), Norm(t[2] - t[0]), Norm(t[2] - t[1])}) / kSteps;
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_GE(exact, sampled - spacing) << "trial " << trial;
    // The height over the inside, where it applies, is the same distance.
    EXPECT_NEAR(std::sqrt(TriangleDistance(t)(q)), exact, 1e-12) << "trial " << trial;
    const DVec3 normal = Cross(t[1] - t[0], t[2] - t[0]);
    if (Norm(normal) > 1e-3) {  // a point over the inside: its height
      const DVec3 over =
          t[0] + 0.2 * (t[1] - t[0]) + 0.3 * (t[2] - t[0]) + (0.5 / Norm(normal)) * normal;
      EXPECT_NEAR(std::sqrt(TriangleDistance(t)(over)), 0.5, 1e-12) << "trial " << trial;
      EXPECT_NEAR(SquaredDistanceToTriangle(over, t[0], t[1], t[2]), 0.25, 1e-12);
    }
  }
}

// Outside the prism over the triangle, TriangleDistance measures only the edges the point's
// projection lies beyond: the same distance as the region tests of SquaredDistanceToTriangle,
// for points near the plane beyond every edge and corner, obtuse and thin triangles included.
TEST(Coverage, TriangleDistanceOutsideThePrismIsTheExactDistance) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int outside = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    DVec3 t[3] = {{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    if (trial % 4 == 1) t[2] = t[0] + 0.9 * (t[1] - t[0]) + DVec3{0.05 * u(rng), 0.05, 0};
    const DVec3 normal = Cross(t[1] - t[0], t[2] - t[0]);
    // In the plane, around the triangle out to twice its size, and a little off it.
    const double a = 3 * u(rng), b = 3 * u(rng), h = (trial % 3 == 0 ? 0.0 : 0.1 * u(rng));
    const DVec3 q = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]) + (h / Norm(normal)) * normal;
    outside += a < 0 || b < 0 || a + b > 1;
    const double exact = SquaredDistanceToTriangle(q, t[0], t[1], t[2]);
    const double scale =
        Dot(q - t[0], q - t[0]) + Dot(t[1] - t[0], t[1] - t[0]) + Dot(t[2] - t[0], t[2] - t[0]);
    EXPECT_NEAR(TriangleDistance(t)(q), exact, 1e-12 * scale) << "trial " << trial;
  }
  EXPECT_GT(outside, 15000);
}

// A tent: the centre (vertex 0) at height h over `sides` neighbours on the unit circle (a
// hexagon unless told).
RawMesh Tent(float h, int sides = 6) {
  RawMesh m;
  m.positions = {0, 0, h};
  for (int i = 0; i < sides; ++i)
    m.positions.insert(m.positions.end(), {float(std::cos(i * 2 * M_PI / sides)),
                                           float(std::sin(i * 2 * M_PI / sides)), 0.0f});
  for (uint32_t i = 0; i < uint32_t(sides); ++i)
    m.triangles.insert(m.triangles.end(), {0, 1 + i, 1 + (i + 1) % sides});
  return m;
}

// Flattening the tent by collapsing its apex onto neighbour 1: the corners of the four new
// faces, and the old faces' ids (the mesh's faces are the tent's, in order).
struct Flattening {
  std::vector<DVec3> corners;
  CoveragePlan plan;
};
Flattening Flatten(const RawMesh& tent) {
  Flattening f;
  auto at = [&](uint32_t v) {
    return DVec3{tent.positions[3 * v], tent.positions[3 * v + 1], tent.positions[3 * v + 2]};
  };
  const uint32_t faces = static_cast<uint32_t>(tent.num_faces());
  for (uint32_t face = 0; face < faces; ++face) f.plan.old_faces.push_back(face);
  for (uint32_t face = 1; face + 1 < faces; ++face) {  // the first and last hold apex - 1
    f.plan.fresh_ids.push_back(face);
    for (uint32_t v : {1u, tent.triangles[3 * face + 1], tent.triangles[3 * face + 2]})
      f.corners.push_back(at(v));
  }
  return f;
}

TEST(Coverage, FlatteningATentIsWithinItsHeightOnly) {
  const RawMesh tent = Tent(0.1f);
  absl::StatusOr<Mesh> mesh = Mesh::Build(tent);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  {
    Coverage tight(*mesh, 0.09);  // the apex is 0.1 from the flat hexagon
    Flattening f = Flatten(tent);
    uint64_t work = 0;
    EXPECT_FALSE(tight.Judge(f.corners, &f.plan, &work));
  }
  Coverage loose(*mesh, 0.11);
  Flattening f = Flatten(tent);
  uint64_t work = 0;
  ASSERT_TRUE(loose.Judge(f.corners, &f.plan, &work));
  EXPECT_GT(work, 0u);
  double reach = 0;
  for (int k = 0; k < 4; ++k) reach = std::max(reach, f.plan.reach[k]);
  EXPECT_GE(reach, 0.1 - 1e-6);  // the apex's distance, certified
  EXPECT_LE(reach, 0.11);
  // The commit: the six input triangles, cut where needed, all held by the four new faces.
  loose.Apply(f.plan);
  double held = 0;
  for (uint32_t face = 0; face < 6; ++face) {
    for (const HeldPiece& p : loose.Held(face)) {
      EXPECT_TRUE(face >= 1 && face <= 4) << "a deleted face holds a piece";
      if (p.partner != kNone && p.partner < face) continue;  // counted with its pair's first
      DVec3 c[3];
      loose.Corners(p.piece, c);
      held += Area(c);
    }
  }
  double input = 0;
  for (uint32_t face = 0; face < 6; ++face) {
    DVec3 c[3];
    loose.Corners(Piece{face, 0}, c);
    input += Area(c);
  }
  EXPECT_NEAR(held, input, 1e-9);
}

// With the faces' own tolerances (the wall rule's limits), a triangle's pieces are held to its
// own: the tent's apex, 0.1 above the new faces, is refused by a run tolerance of 0.11 once one
// of the six triangles at it has 0.09, and taken when all have 0.105, each new face certified
// within that.
TEST(Coverage, EachInputTriangleHeldWithinItsOwnLimit) {
  const RawMesh tent = Tent(0.1f);
  absl::StatusOr<Mesh> mesh = Mesh::Build(tent);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  mesh->EnsureFaceAttrs();
  FaceAttrQ* attrs = mesh->face_attrs();
  for (uint32_t face = 0; face < 6; ++face) attrs[face].limit = face == 3 ? 0.09f : 0.0f;
  {
    Coverage limited(*mesh, 0.11, /*face_limits=*/true);
    Flattening f = Flatten(tent);
    uint64_t work = 0;
    EXPECT_FALSE(limited.Judge(f.corners, &f.plan, &work));
    Coverage unlimited(*mesh, 0.11);  // the same mesh, the limits not asked for
    Flattening g = Flatten(tent);
    EXPECT_TRUE(unlimited.Judge(g.corners, &g.plan, &work));
  }
  for (uint32_t face = 0; face < 6; ++face) attrs[face].limit = 0.105f;
  Coverage limited(*mesh, 0.11, /*face_limits=*/true);
  Flattening f = Flatten(tent);
  uint64_t work = 0;
  ASSERT_TRUE(limited.Judge(f.corners, &f.plan, &work));
  for (int k = 0; k < 4; ++k) EXPECT_LE(f.plan.reach[k], 0.105) << "new face " << k;
}

// Builds the coverage of `input` and judges the replacement `make` gives for it: whether it is
// within the tolerance, and the largest reach of its new faces.
struct Judged {
  bool within;
  double reach;
};
template <class Make>
Judged JudgeReplacement(const RawMesh& input, double tolerance, Make make) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(input);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  if (!mesh.ok()) return {false, 0};
  Coverage coverage(*mesh, tolerance);
  Flattening f = make(input);
  uint64_t work = 0;
  Judged judged{coverage.Judge(f.corners, &f.plan, &work), 0};
  for (size_t k = 0; k < f.plan.fresh_ids.size(); ++k)
    judged.reach = std::max(judged.reach, f.plan.reach[k]);
  return judged;
}

// A pentagonal tent lower than the tolerance, flattened: the apex's shadow is inside a new face,
// where no input triangle or pair across an edge holds a part around it whole, and parts small
// enough for the centre's test (radius under the tolerance, 0.004) lie below the deepest level.
// The apex's fan, flat to within its height and convex seen from above, takes them whole:
// certified within the height, and not below it.
TEST(Coverage, AFlatFanTakesThePartsAroundItsVertexWhole) {
  for (const float h : {0.0f, 0.002f}) {
    const Judged judged = JudgeReplacement(Tent(h, 5), 0.004, Flatten);
    ASSERT_TRUE(judged.within) << "height " << h;
    EXPECT_GE(judged.reach, h - 1e-6);
    EXPECT_LE(judged.reach, 0.004);
  }
  // Higher than the tolerance, the fan is no certificate.
  EXPECT_FALSE(JudgeReplacement(Tent(0.005f, 5), 0.004, Flatten).within);
}

// The unit square as an n x n grid, split along its diagonals, its vertices raised by
// `height` in a checkerboard (so that no fan or pair of input triangles is flat to within the
// tolerance used below), without the two triangles of cell (hole, hole) when hole >= 0.
RawMesh Checkerboard(int n, float height, int hole = -1) {
  RawMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.positions.insert(m.positions.end(),
                         {float(i) / n, float(j) / n, (i + j) % 2 == 0 ? height : -height});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i == hole && j == hole) continue;
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    }
  return m;
}

// The grid replaced by the square's two triangles, at height 0, split along the diagonal the
// grid's cells are not (so that no part of their subdivision lies over one input triangle).
Flattening Square(const RawMesh& grid) {
  Flattening f;
  for (uint32_t face = 0; face < grid.num_faces(); ++face) f.plan.old_faces.push_back(face);
  f.plan.fresh_ids = {0, 1};
  f.corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  return f;
}

// Every input point is within 0.0035 of the square and back; no input triangle, pair or fan
// holds a part of the square whole unless it is smaller than the deepest level's, but the
// input seen from above covers the square within the slab: the shadow certificate takes it.
TEST(Coverage, AHeightFieldInTheSlabTakesTheNewFaceWhole) {
  const Judged judged = JudgeReplacement(Checkerboard(16, 0.0035f), 0.004, Square);
  ASSERT_TRUE(judged.within);
  EXPECT_GE(judged.reach, 0.0035 - 1e-6);
  EXPECT_LE(judged.reach, 0.004);
  // Above the tolerance, refused.
  EXPECT_FALSE(JudgeReplacement(Checkerboard(16, 0.0045f), 0.004, Square).within);
}

// The shadow certificate keeps a triangle that crosses R's border when its part over R lies in
// the slab: the largest |height| over the clip, against a dense sampling of the triangle's
// points over R (never below it; above it by at most a sample's height step), and none when
// the shadows do not meet.
TEST(Coverage, ClippedHeightIsTheHighestPointOverR) {
  using P = CoveragePlan::Point2;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto turn = [](const P& a, const P& b, const P& p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
  };
  const P r[3] = {{0, 0}, {1, 0}, {0.3, 0.9}};
  int clipped = 0, apart = 0;
  for (int trial = 0; trial < 300; ++trial) {
    P xy[3] = {{u(rng), u(rng)}, {u(rng) + 0.5, u(rng)}, {u(rng), u(rng) + 0.5}};
    if (turn(xy[0], xy[1], xy[2]) < 0) std::swap(xy[1], xy[2]);
    if (trial % 10 == 0)
      for (P& p : xy) p.x += 3;  // its shadow beside R's
    const double h[3] = {u(rng), u(rng), u(rng)};
    const double highest = ClippedHeight(xy, h, r);
    constexpr int kSteps = 300;
    double sampled = -1, step = 0;
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double a = double(i) / kSteps, b = double(j) / kSteps;
        const P p{xy[0].x + a * (xy[1].x - xy[0].x) + b * (xy[2].x - xy[0].x),
                  xy[0].y + a * (xy[1].y - xy[0].y) + b * (xy[2].y - xy[0].y)};
        if (turn(r[0], r[1], p) < 0 || turn(r[1], r[2], p) < 0 || turn(r[2], r[0], p) < 0) continue;
        sampled = std::max(sampled, std::fabs(h[0] + a * (h[1] - h[0]) + b * (h[2] - h[0])));
      }
    step = (std::fabs(h[1] - h[0]) + std::fabs(h[2] - h[0])) / kSteps;
    if (sampled < 0) {
      ++apart;
      if (trial % 10 == 0) {
        EXPECT_LT(highest, 0) << "trial " << trial;
      }
      continue;
    }
    ++clipped;
    EXPECT_GE(highest, sampled - 1e-12) << "trial " << trial;
    EXPECT_LE(highest, sampled + 2 * step + 1e-12) << "trial " << trial;
  }
  EXPECT_GT(clipped, 200);
  EXPECT_GE(apart, 30);
}

// A hole in the input under the square: its middle is 0.03 from any input point, so the square
// is not within 0.004 of the input; the hole's edges end the shadow inside the square.
TEST(Coverage, AHoleUnderTheNewFaceIsRefused) {
  EXPECT_FALSE(JudgeReplacement(Checkerboard(16, 0.0035f, 5), 0.004, Square).within);
}

// The unit square as two triangles, split along the diagonal from (0, 0) to (1, 1).
RawMesh FlatSquare() {
  RawMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  m.triangles = {0, 1, 2, 0, 2, 3};
  return m;
}

// The square split along its other diagonal, the new faces taking the old ids 0 and 1.
Flattening FlippedSquare() {
  Flattening f;
  f.plan.old_faces = {0, 1};
  f.plan.fresh_ids = {0, 1};
  f.corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  return f;
}

// Every list holds two whole input triangles, each with the other face as its partner.
void ExpectPairHoldsBothWhole(const Coverage& coverage) {
  for (uint32_t face : {0u, 1u}) {
    const std::vector<HeldPiece> held = coverage.Held(face);
    ASSERT_EQ(held.size(), 2u) << "face " << face;
    for (const HeldPiece& p : held) {
      EXPECT_EQ(p.piece.level(), 0) << "face " << face;
      EXPECT_EQ(p.partner, 1 - face);
    }
  }
}

// Each input triangle straddles the new diagonal: one new face holds only what lies on its
// side, so alone they would cut the triangles down to the tolerance's size along the edge (and
// give up at the deepest level). Together the two new faces are a flat convex quad, the
// square itself, and take both triangles whole. Rewriting one of the two (as itself) takes the
// pieces out of the other's list too, and gives them to the same pair again, once.
TEST(Coverage, TwoNewFacesAcrossAnEdgeHoldWhatStraddlesItTogether) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(FlatSquare());
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  Coverage coverage(*mesh, 1e-3);
  Flattening flip = FlippedSquare();
  uint64_t work = 0;
  ASSERT_TRUE(coverage.Judge(flip.corners, &flip.plan, &work));
  coverage.Apply(flip.plan);
  ExpectPairHoldsBothWhole(coverage);
  // The mesh as the kernel's commit leaves it (the coverage reads the faces it keeps there).
  RawMesh flipped = FlatSquare();
  flipped.triangles = {0, 1, 3, 1, 2, 3};
  absl::StatusOr<Mesh> after = Mesh::Build(flipped);
  ASSERT_TRUE(after.ok()) << after.status();
  *mesh = *std::move(after);
  EXPECT_TRUE(coverage.Audit().ok()) << coverage.Audit();

  Flattening again;
  again.plan.old_faces = {0};
  again.plan.fresh_ids = {0};
  again.corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  ASSERT_TRUE(coverage.Judge(again.corners, &again.plan, &work));
  EXPECT_EQ(again.plan.kept, std::vector<uint32_t>{1});
  coverage.Apply(again.plan);
  ExpectPairHoldsBothWhole(coverage);

  // Face 0 lifted 0.01 at one corner, beyond the tolerance of what it held: refused.
  Flattening lifted;
  lifted.plan.old_faces = {0};
  lifted.plan.fresh_ids = {0};
  lifted.corners = {{0, 0, 0.01}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_FALSE(coverage.Judge(lifted.corners, &lifted.plan, &work));
}

// The square folded along one diagonal (a valley 0.1 deep at its corners 1 and 3), the new
// faces along the other (a ridge): each input triangle straddles the ridge, and the two new
// faces' hull lies 0.1 from them, as far as the surfaces are apart. Cut between them along the
// ridge, each side is within 0.0990 of its face (the valley's middle, under the ridge's): the
// pair takes both input triangles whole at a tolerance just above that, and refuses below.
TEST(Coverage, TwoNewFacesAcrossABentEdgeHoldWhatStraddlesItTogether) {
  RawMesh folded = FlatSquare();
  folded.positions[5] = folded.positions[11] = 0.1f;
  absl::StatusOr<Mesh> mesh = Mesh::Build(folded);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  const double h = folded.positions[5];
  Flattening flip = FlippedSquare();
  for (DVec3& c : flip.corners)
    if (c.x + c.y == 1) c.z = h;
  const double apart = h / std::sqrt(1 + 2 * h * h);  // the valley's middle to the ridge's faces
  uint64_t work = 0;
  {
    Coverage tight(*mesh, apart * 0.999);
    Flattening f = flip;
    EXPECT_FALSE(tight.Judge(f.corners, &f.plan, &work));
  }
  Coverage coverage(*mesh, apart * 1.005);
  ASSERT_TRUE(coverage.Judge(flip.corners, &flip.plan, &work));
  coverage.Apply(flip.plan);
  ExpectPairHoldsBothWhole(coverage);
}

// The audit of what the commits built: the input as built passes; a commit that leaves a
// piece to no face is reported, naming the input triangle.
TEST(Coverage, AuditFindsAnInputTriangleNoFaceHolds) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(FlatSquare());
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  Coverage coverage(*mesh, 1e-3);
  EXPECT_TRUE(coverage.Audit().ok());
  CoveragePlan dropped;
  dropped.old_faces = {1};  // rewritten, its triangle given to no new face
  coverage.Apply(dropped);
  const absl::Status audit = coverage.Audit();
  EXPECT_EQ(audit.code(), absl::StatusCode::kInternal);
  EXPECT_NE(audit.message().find("input triangle 1 has 0 of its area"), std::string::npos) << audit;
}

// The tolerance alone decides: no volume bound, no minimum angle, normals free.
SimplifyOptions BoundOnly(DeviationCheck check, int threads, double tolerance_relative) {
  SimplifyOptions o;
  o.threads = threads;
  o.tolerance_relative = tolerance_relative;
  o.max_volume_change = 0;
  o.min_angle_deg = 0;
  o.max_normal_deviation_deg = 180;
  o.deviation_check = check;
  return o;
}

// Whole runs on a torus: the measured check keeps fewer vertices than the mapped bound at the
// same tolerance, stays within it by its own account, and gives the same output for any number
// of threads (the deterministic schedule).
TEST(Coverage, RunsKeepFewerVerticesThanTheMappedBound) {
  const RawMesh torus = testing::MakeTorus(48, 24);
  auto run = [&](DeviationCheck check, int threads, RawMesh* out) {
    absl::StatusOr<Mesh> mesh = Mesh::Build(torus);
    EXPECT_TRUE(mesh.ok()) << mesh.status();
    absl::StatusOr<SimplifyResult> r = Simplify(*mesh, BoundOnly(check, threads, 0.01));
    EXPECT_TRUE(r.ok()) << r.status();
    if (out != nullptr) *out = mesh->ToRaw();
    return *r;
  };
  RawMesh one, two;
  const SimplifyResult mapped = run(DeviationCheck::kMapped, 1, nullptr);
  const SimplifyResult measured = run(DeviationCheck::kMeasured, 1, &one);
  run(DeviationCheck::kMeasured, 2, &two);
  EXPECT_LT(measured.output_vertices, mapped.output_vertices);
  EXPECT_LE(measured.deviation_bound, measured.tolerance_abs);
  EXPECT_GT(measured.deviation_bound, 0.5 * measured.tolerance_abs);  // it uses the tolerance
  EXPECT_EQ(one.positions, two.positions);
  EXPECT_EQ(one.triangles, two.triangles);
}

// With the tolerance measured, placement is tried where the tolerance refuses a half-edge
// collapse too (no mass budget here), and keeps fewer vertices; the mapped bound never gets it.
TEST(Coverage, PlacementWhereTheMeasuredToleranceRefuses) {
  const RawMesh torus = testing::MakeTorus(48, 24);
  auto run = [&](DeviationCheck check, Placement placement) {
    absl::StatusOr<Mesh> mesh = Mesh::Build(torus);
    EXPECT_TRUE(mesh.ok()) << mesh.status();
    SimplifyOptions o = BoundOnly(check, 2, 0.005);
    o.placement = placement;
    absl::StatusOr<SimplifyResult> r = Simplify(*mesh, o);
    EXPECT_TRUE(r.ok()) << r.status();
    uint64_t placed = 0;
    for (const PassStats& p : r->passes) placed += p.placed;
    EXPECT_LE(r->deviation_bound, r->tolerance_abs);
    return std::pair{r->output_vertices, placed};
  };
  const auto [endpoint_vertices, none] = run(DeviationCheck::kMeasured, Placement::kEndpoint);
  const auto [placed_vertices, placed] = run(DeviationCheck::kMeasured, Placement::kOptimal);
  const auto [mapped_vertices, mapped_placed] = run(DeviationCheck::kMapped, Placement::kOptimal);
  EXPECT_EQ(none, 0u);
  EXPECT_GT(placed, 0u);
  EXPECT_LT(placed_vertices, endpoint_vertices);
  EXPECT_EQ(mapped_placed, 0u);
  (void)mapped_vertices;
}

// On a part with curved creases (rotor_small at 1 %, the mass budgets on), V and Vd on one
// feature line may merge at a point off it, where a half-edge slide along the line would cut
// the curve's volume: the measured check holds the line's pieces, the mapped bound lays the old
// line onto the new one. Either way the same output for one and two threads.
TEST(Coverage, PlacementOnFeatureLinesWithEitherCheck) {
  const RawMesh rotor = testing::LoadTestMesh("rotor_small.off");
  auto run = [&](DeviationCheck check, int threads, RawMesh* out) {
    SimplifyOptions o;
    o.threads = threads;
    o.tolerance_relative = 0.01;
    o.max_volume_change = 0.001;
    o.max_inertia_change = 0.005;
    o.placement = Placement::kOptimal;
    o.deviation_check = check;
    const testing::SimplifyRun r = testing::SimplifyChecked(rotor, o);
    if (out != nullptr) *out = r.output;
    uint64_t placed = 0, on_lines = 0;
    for (const PassStats& p : r.result.passes) {
      placed += p.placed;
      on_lines += p.placed_on_lines;
    }
    EXPECT_LE(on_lines, placed);
    EXPECT_LE(std::abs(r.result.volume_change), 0.001);
    EXPECT_LE(r.result.deviation_bound, r.result.tolerance_abs);
    return on_lines;
  };
  for (const DeviationCheck check : {DeviationCheck::kMeasured, DeviationCheck::kMapped}) {
    RawMesh one, two;
    EXPECT_GT(run(check, 1, &one), 0u);
    run(check, 2, &two);
    EXPECT_EQ(one.positions, two.positions);
    EXPECT_EQ(one.triangles, two.triangles);
  }
}

// A placed vertex is judged where the floats it is stored as put it. rotor_small 100,000 of its
// diagonals from the origin, where floats are 0.0156 apart (1.8 % of the part): built with GCC
// 12, the kernel judged two of P's coordinates unrounded (engine/vec.h, StoredPosition), and
// the run's audit found an input piece beyond the tolerance of the face holding it.
TEST(Coverage, PlacedVertexJudgedWhereItIsStored) {
  RawMesh far = testing::LoadTestMesh("rotor_small.off");
  const double offset[3] = {1e5, 2e5, -3e4};
  for (size_t i = 0; i < far.positions.size(); ++i)
    far.positions[i] = static_cast<float>(double(far.positions[i]) + offset[i % 3]);
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(far, RepairOptions{});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  SimplifyOptions o;
  o.threads = 1;
  o.tolerance_relative = 0.01;
  o.placement = Placement::kOptimal;
  o.deviation_check = DeviationCheck::kMeasured;
  absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, o);
  ASSERT_TRUE(result.ok()) << result.status();  // the audit of every held piece passed
  uint64_t placed = 0;
  for (const PassStats& p : result->passes) placed += p.placed;
  EXPECT_GT(placed, 0u);
  EXPECT_LT(result->output_vertices, result->input_vertices / 2);
}

TEST(Coverage, CellBackEndRefusesTheMeasuredCheck) {
  SimplifyOptions o;
  o.backend = Backend::kCell;
  o.deviation_check = DeviationCheck::kMeasured;
  const absl::Status s = ValidateOptions(o);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("native back end only"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace femsimp
