// The judge on cases whose answers are known in closed form, and its two Hausdorff methods
// against each other on a real mesh.
#include "tests/judge/judge.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "engine/crossings.h"
#include "tests/support/meshes.h"

namespace femsimp::judge {
namespace {

// Axis-aligned box, outward counter-clockwise faces; with groups, one group per side
// (0: -x, 1: +x, 2: -y, 3: +y, 4: -z, 5: +z).
RawMesh Box(Vec3 lo, Vec3 hi, bool groups = false) {
  RawMesh m;
  for (int i = 0; i < 8; ++i) {
    m.positions.push_back(static_cast<float>(i & 1 ? hi[0] : lo[0]));
    m.positions.push_back(static_cast<float>(i & 2 ? hi[1] : lo[1]));
    m.positions.push_back(static_cast<float>(i & 4 ? hi[2] : lo[2]));
  }
  // Each side as a quad a b c d, counter-clockwise seen from outside.
  const uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (uint32_t s = 0; s < 6; ++s) {
    const uint32_t* q = quads[s];
    m.triangles.insert(m.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    if (groups) m.face_groups.insert(m.face_groups.end(), {s, s});
  }
  return m;
}

RawMesh UnitCube(bool groups = false) { return Box({0, 0, 0}, {1, 1, 1}, groups); }

RawMesh Translated(RawMesh m, Vec3 d) {
  for (size_t i = 0; i < m.positions.size(); ++i) m.positions[i] += static_cast<float>(d[i % 3]);
  return m;
}

// The unit square in z = 0 as a fan of four triangles around its centre, which is lifted to
// height h.
RawMesh SquareFan(double h) {
  RawMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, static_cast<float>(h)};
  m.triangles = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
  return m;
}

RawMesh Tetrahedron(Vec3 o) {
  RawMesh m;
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& q : p)
    for (int k = 0; k < 3; ++k) m.positions.push_back(static_cast<float>(q[k] + o[k]));
  m.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  return m;
}

RawMesh Merge(const RawMesh& a, const RawMesh& b) {
  RawMesh m = a;
  const uint32_t offset = static_cast<uint32_t>(a.num_vertices());
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t v : b.triangles) m.triangles.push_back(v + offset);
  return m;
}

constexpr double kError = 1e-4;
// Coordinates pass through float: a hair of slack on top of the judge's own error.
constexpr double kFloat = 1e-6;

// A certified lower bound within `error` of the truth.
void ExpectCertified(double measured, double truth, double error) {
  EXPECT_LE(measured, truth + kFloat);
  EXPECT_GE(measured, truth - error - kFloat);
}

TEST(JudgeHausdorff, IdenticalMeshesAreAtZero) {
  const Hausdorff h = HausdorffDistance(UnitCube(), UnitCube(), kError);
  EXPECT_LE(h.two_sided(), kError);
}

TEST(JudgeHausdorff, ShiftedCube) {
  const Hausdorff h = HausdorffDistance(UnitCube(), Translated(UnitCube(), {0.1, 0, 0}), kError);
  ExpectCertified(h.a_to_b, 0.1, kError);
  ExpectCertified(h.b_to_a, 0.1, kError);
  EXPECT_EQ(h.error, kError);
}

TEST(JudgeHausdorff, ScaledCubeIsAsymmetric) {
  // Inner cube to outer: a face is 0.1 from its parallel face. Outer to inner: the outer
  // corners are 0.1 * sqrt(3) from the inner ones.
  const RawMesh inner = Box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  const RawMesh outer = Box({-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6});
  const Hausdorff h = HausdorffDistance(inner, outer, kError);
  ExpectCertified(h.a_to_b, 0.1, kError);
  ExpectCertified(h.b_to_a, 0.1 * std::sqrt(3.0), kError);
  ExpectCertified(h.two_sided(), 0.1 * std::sqrt(3.0), kError);
}

TEST(JudgeHausdorff, BumpedSquare) {
  // The apex is h above the flat square; the flat centre is h d / sqrt(h^2 + d^2) from the
  // four tilted faces, whose bases are d = 0.5 away.
  const double h = 0.1, d = 0.5;
  const Hausdorff hd = HausdorffDistance(SquareFan(0.0), SquareFan(h), kError);
  ExpectCertified(hd.a_to_b, h * d / std::sqrt(h * h + d * d), kError);
  ExpectCertified(hd.b_to_a, h, kError);
}

TEST(JudgeHausdorff, SamplingAgreesOnAnalyticCases) {
  const double spacing = 0.01, covering = spacing / std::sqrt(3.0);
  const RawMesh inner = Box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  const RawMesh outer = Box({-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6});
  ExpectCertified(SampledHausdorff(inner, outer, spacing), 0.1, covering);
  ExpectCertified(SampledHausdorff(outer, inner, spacing), 0.1 * std::sqrt(3.0), covering);
  ExpectCertified(SampledHausdorff(SquareFan(0.0), SquareFan(0.1), spacing), 0.05 / std::sqrt(0.26),
                  covering);
}

// fandisk against a copy whose vertices moved randomly by up to 0.2 % of the diagonal: both
// methods bracket the same true distance, so their intervals must overlap.
TEST(JudgeHausdorff, BoundedErrorAndSamplingAgreeOnFandisk) {
  const RawMesh a = testing::LoadTestMesh("fandisk.off");
  ASSERT_GT(a.num_faces(), 0u);
  const double diag = BoundingBoxDiagonal(a);
  RawMesh b = a;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> jitter(-0.002f * float(diag) / std::sqrt(3.0f),
                                               0.002f * float(diag) / std::sqrt(3.0f));
  for (float& x : b.positions) x += jitter(rng);
  const double error = HausdorffErrorFor(0.001 * diag);
  const Hausdorff h = HausdorffDistance(a, b, error);
  EXPECT_GT(h.two_sided(), 0.0005 * diag);
  EXPECT_LT(h.two_sided(), 0.002 * diag + error);
  const double spacing = 0.001 * diag, covering = spacing / std::sqrt(3.0);
  const double ab = SampledHausdorff(a, b, spacing), ba = SampledHausdorff(b, a, spacing);
  EXPECT_LE(ab, h.a_to_b + error + kFloat);
  EXPECT_GE(ab + covering, h.a_to_b - kFloat);
  EXPECT_LE(ba, h.b_to_a + error + kFloat);
  EXPECT_GE(ba + covering, h.b_to_a - kFloat);
}

TEST(JudgeHausdorff, PerGroup) {
  const auto per_group =
      GroupHausdorffDistances(UnitCube(true), Translated(UnitCube(true), {0.1, 0, 0}), kError);
  ASSERT_EQ(per_group.size(), 6u);
  for (const auto& [group, h] : per_group) ExpectCertified(h.two_sided(), 0.1, kError);
  // A group that vanished is infinitely far.
  RawMesh five = UnitCube(true);
  five.triangles.resize(30);
  five.face_groups.resize(10);
  const auto missing = GroupHausdorffDistances(UnitCube(true), five, kError);
  EXPECT_TRUE(std::isinf(missing.at(5).two_sided()));
  EXPECT_LE(missing.at(0).two_sided(), kError);
}

TEST(JudgeIntersections, CubesAndOverlaps) {
  EXPECT_FALSE(SelfIntersects(UnitCube()));
  EXPECT_FALSE(SelfIntersects(Merge(UnitCube(), Translated(UnitCube(), {2, 0, 0}))));
  EXPECT_TRUE(SelfIntersects(Merge(UnitCube(), Translated(UnitCube(), {0.5, 0.5, 0.5}))));
  // A fold: the bumped square pushed through by a face from below.
  RawMesh folded = SquareFan(0.1);
  folded.positions.insert(folded.positions.end(),
                          {0.5f, 0.2f, -0.1f, 0.5f, 0.8f, -0.1f, 0.5f, 0.5f, 0.3f});
  folded.triangles.insert(folded.triangles.end(), {5, 6, 7});
  EXPECT_TRUE(SelfIntersects(folded));
}

// A box standing on a plate, the two triangulated apart: the judge's exact count of the faces
// overlapping in the contact's plane is femsimp's (engine/crossings.h); lifted by a thousandth,
// neither finds one.
TEST(JudgeIntersections, OverlapsInOnePlaneAsFemsimpCountsThem) {
  RawMesh stacked = testing::MakeBox({4, 3, 1}, {4, 3, 1});
  testing::Append(stacked, testing::MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {0.75f, 0.5f, 1.0f});
  const size_t pairs = SoupOverlappingPairs(stacked);
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(pairs, FindCrossings(stacked).overlaps.pairs);
  EXPECT_EQ(SoupOverlappingPairs(UnitCube()), 0u);
  EXPECT_EQ(SoupOverlappingPairs(testing::MakeTorus(24, 12)), 0u);
  RawMesh lifted = testing::MakeBox({4, 3, 1}, {4, 3, 1});
  testing::Append(lifted, testing::MakeBox({1.5, 1.25, 2}, {3, 2, 2}), {0.75f, 0.5f, 1.001f});
  EXPECT_EQ(SoupOverlappingPairs(lifted), 0u);
  EXPECT_EQ(FindCrossings(lifted).overlaps.pairs, 0u);
}

// The soup count agrees with CGAL's mesh count where the mesh test applies, and sees the parts
// of an assembly touch along their shared edge where the mesh test (copies) sees crossings.
TEST(JudgeIntersections, SoupCountAgreesAndTakesSeamsAsShared) {
  const RawMesh overlapping = Merge(UnitCube(), Translated(UnitCube(), {0.5, 0.5, 0.5}));
  RawMesh folded = SquareFan(0.1);
  folded.positions.insert(folded.positions.end(),
                          {0.5f, 0.2f, -0.1f, 0.5f, 0.8f, -0.1f, 0.5f, 0.5f, 0.3f});
  folded.triangles.insert(folded.triangles.end(), {5, 6, 7});
  for (const RawMesh& m : {UnitCube(), overlapping, folded, testing::LoadTestMesh("fandisk.off")})
    EXPECT_EQ(SoupSelfIntersectingPairs(m), SelfIntersectingPairs(m));
  EXPECT_GT(SoupSelfIntersectingPairs(overlapping), 0u);
  EXPECT_GT(SoupSelfIntersectingPairs(folded), 0u);

  // Two cubes sharing the edge x = y = 1, welded there: four faces around it.
  RawMesh pair = Merge(UnitCube(), Translated(UnitCube(), {1, 1, 0}));
  std::map<std::array<float, 3>, uint32_t> first;
  for (uint32_t& v : pair.triangles) {
    const std::array<float, 3> p{pair.positions[3 * v], pair.positions[3 * v + 1],
                                 pair.positions[3 * v + 2]};
    v = first.try_emplace(p, v).first->second;
  }
  EXPECT_EQ(SoupSelfIntersectingPairs(pair), 0u);
  // Pushed into each other by a tenth, they cross.
  RawMesh crossing = Merge(UnitCube(), Translated(UnitCube(), {0.9, 0.9, 0}));
  EXPECT_GT(SoupSelfIntersectingPairs(crossing), 0u);
}

TEST(JudgeTopology, ClosedOpenAndGenus) {
  const Topology cube = ComputeTopology(UnitCube());
  EXPECT_TRUE(cube.closed_manifold());
  EXPECT_EQ(cube.euler(), 2);
  EXPECT_EQ(cube.genus(), 0);
  EXPECT_EQ(cube.components, 1);

  const Topology square = ComputeTopology(SquareFan(0.0));
  EXPECT_TRUE(square.manifold());
  EXPECT_FALSE(square.closed_manifold());
  EXPECT_EQ(square.boundary_edges, 4);
  EXPECT_EQ(square.boundary_loops, 1);
  EXPECT_EQ(square.genus(), 0);

  const Topology torus = ComputeTopology(testing::MakeTorus(12, 8, 2.0, 0.5));
  EXPECT_TRUE(torus.closed_manifold());
  EXPECT_EQ(torus.euler(), 0);
  EXPECT_EQ(torus.genus(), 1);

  const Topology two = ComputeTopology(
      Merge(UnitCube(), Translated(testing::MakeTorus(12, 8, 2.0, 0.5), {5, 0, 0})));
  EXPECT_EQ(two.components, 2);
  EXPECT_EQ(two.genus(), 1);
}

TEST(JudgeTopology, FindsNonManifoldAndMisoriented) {
  // Two cubes sharing corner 7 of the first: one vertex, two fans.
  RawMesh touching = Merge(UnitCube(), Translated(UnitCube(), {1, 1, 1}));
  for (uint32_t& v : touching.triangles)
    if (v == 8) v = 7;
  const Topology t = ComputeTopology(touching);
  EXPECT_EQ(t.nonmanifold_vertices, 1);
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_FALSE(t.closed_manifold());

  RawMesh fin = SquareFan(0.0);
  fin.positions.insert(fin.positions.end(), {0.5f, 0.0f, 1.0f, 0.5f, 0.0f, -1.0f});
  fin.triangles.insert(fin.triangles.end(), {1, 0, 5, 0, 1, 6});  // three faces on edge 0-1
  EXPECT_EQ(ComputeTopology(fin).nonmanifold_edges, 1);

  RawMesh flipped = UnitCube();
  std::swap(flipped.triangles[0], flipped.triangles[1]);
  EXPECT_EQ(ComputeTopology(flipped).misoriented_edges, 3);
  EXPECT_FALSE(ComputeTopology(flipped).closed_manifold());
}

TEST(JudgeIntegrals, CubeAndTetrahedron) {
  const Solid cube = SolidProperties(Translated(UnitCube(), {3, -2, 7}));
  EXPECT_NEAR(cube.volume, 1.0, 1e-6);
  EXPECT_NEAR(cube.centroid[0], 3.5, 1e-6);
  EXPECT_NEAR(cube.centroid[1], -1.5, 1e-6);
  EXPECT_NEAR(cube.centroid[2], 7.5, 1e-6);

  const Solid tet = SolidProperties(Tetrahedron({1, 2, 3}));
  EXPECT_NEAR(tet.volume, 1.0 / 6.0, 1e-6);
  EXPECT_NEAR(tet.centroid[0], 1.25, 1e-6);
  EXPECT_NEAR(tet.centroid[1], 2.25, 1e-6);
  EXPECT_NEAR(tet.centroid[2], 3.25, 1e-6);

  RawMesh inside_out = UnitCube();
  for (size_t f = 0; f < inside_out.num_faces(); ++f)
    std::swap(inside_out.triangles[3 * f + 1], inside_out.triangles[3 * f + 2]);
  EXPECT_NEAR(SolidProperties(inside_out).volume, -1.0, 1e-6);

  const Surface s = SurfaceProperties(SquareFan(0.0));
  EXPECT_NEAR(s.area, 1.0, 1e-6);
  EXPECT_NEAR(s.centroid[0], 0.5, 1e-6);
  EXPECT_NEAR(s.centroid[1], 0.5, 1e-6);
  // The surface centroid of an open box (no top) sits below its middle: 5 sides, the bottom
  // at z = 0 and four walls centred at z = 0.5, so z = 2 / 5.
  RawMesh open = UnitCube();
  open.triangles.resize(30);
  EXPECT_NEAR(SurfaceProperties(open).centroid[2], 0.4, 1e-6);
}

TEST(JudgeIntegrals, PressureResultantPerGroup) {
  // p = z at each face's centroid: exact for a linear field on flat faces. Over the closed
  // cube the resultant is the gradient times the volume, (0, 0, 1).
  RawMesh cube = UnitCube(true);
  FaceField p{"pressure", {}};
  for (size_t f = 0; f < cube.num_faces(); ++f) {
    float z = 0;
    for (int i = 0; i < 3; ++i) z += cube.positions[3 * cube.triangles[3 * f + i] + 2] / 3;
    p.values.push_back(z);
  }
  cube.face_fields.push_back(p);
  const auto loads = FieldResultants(cube, 0);
  ASSERT_EQ(loads.size(), 6u);
  Vec3 total{};
  for (const auto& [group, load] : loads)
    for (int k = 0; k < 3; ++k) total[k] += load.force[k];
  EXPECT_NEAR(total[0], 0.0, 1e-6);
  EXPECT_NEAR(total[1], 0.0, 1e-6);
  EXPECT_NEAR(total[2], 1.0, 1e-6);
  // +x side: mean pressure 0.5 on unit area along +x; bottom: no load.
  EXPECT_NEAR(loads.at(1).force[0], 0.5, 1e-6);
  EXPECT_NEAR(loads.at(1).abs_load, 0.5, 1e-6);
  EXPECT_NEAR(loads.at(1).area, 1.0, 1e-6);
  EXPECT_NEAR(loads.at(4).abs_load, 0.0, 1e-9);
  EXPECT_NEAR(loads.at(5).force[2], 1.0, 1e-6);

  // Doubling the pressure on the +x side changes its resultant by 100 % of its load.
  RawMesh changed = cube;
  for (size_t f = 0; f < changed.num_faces(); ++f)
    if (changed.face_groups[f] == 1) changed.face_fields[0].values[f] *= 2;
  const auto change = RelativeResultantChange(loads, FieldResultants(changed, 0));
  EXPECT_NEAR(change.at(1), 1.0, 1e-6);
  EXPECT_NEAR(change.at(3), 0.0, 1e-9);
  // Without groups every face is in group 0.
  RawMesh plain = cube;
  plain.face_groups.clear();
  const auto one = FieldResultants(plain, 0);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one.at(0).force[2], 1.0, 1e-6);
  EXPECT_EQ(one.at(0).faces, 12u);
}

TEST(JudgeFeatures, CubeEdgesBoundariesAndGroups) {
  const FeatureEdges cube = ExtractFeatureEdges(UnitCube(), 30.0);
  EXPECT_EQ(cube.segments.size(), 12u);  // the face diagonals are flat
  EXPECT_EQ(cube.sharp, 12u);
  EXPECT_EQ(ExtractFeatureEdges(UnitCube(), 90.5).segments.size(), 0u);
  const FeatureEdges grouped = ExtractFeatureEdges(UnitCube(true), 180.0);
  EXPECT_EQ(grouped.group_border, 12u);
  EXPECT_EQ(grouped.segments.size(), 12u);
  const FeatureEdges square = ExtractFeatureEdges(SquareFan(0.05), 30.0);
  EXPECT_EQ(square.boundary, 4u);
  EXPECT_EQ(square.segments.size(), 4u);  // a 0.05 bump: ~8 degrees between neighbours
  EXPECT_EQ(ExtractFeatureEdges(SquareFan(0.5), 30.0).sharp, 4u);  // 60 degrees
}

TEST(JudgeFeatures, CoverageMeasuresHowFarLinesMoved) {
  const double spacing = 0.01;
  const FeatureCoverage same = CheckFeatureCoverage(UnitCube(), UnitCube(), 30.0, spacing);
  EXPECT_EQ(same.original_edges, 12u);
  EXPECT_EQ(same.simplified_edges, 12u);
  EXPECT_GE(same.samples, 12u * 100u);
  EXPECT_NEAR(same.max_distance, 0.0, kFloat);
  EXPECT_EQ(same.error, spacing / 2);

  const FeatureCoverage shifted =
      CheckFeatureCoverage(UnitCube(), Translated(UnitCube(), {0.02, 0, 0}), 30.0, spacing);
  EXPECT_NEAR(shifted.max_distance, 0.02, kFloat);
  EXPECT_NEAR(shifted.reverse_max_distance, 0.02, kFloat);

  // The sharp pyramid's four ridges (60 degrees) are lost when it is flattened to a 0.05 bump
  // (~8 degrees): the ridge tops are then as far as 0.5 from the square's border, its only
  // feature line left; the other way round every border point is still a feature point.
  const FeatureCoverage lost = CheckFeatureCoverage(SquareFan(0.5), SquareFan(0.05), 30.0, spacing);
  EXPECT_EQ(lost.original_edges, 8u);
  EXPECT_EQ(lost.simplified_edges, 4u);
  EXPECT_NEAR(lost.max_distance, std::sqrt(0.25 + 0.25), 1e-6);  // the apex
  EXPECT_NEAR(lost.worst_point[2], 0.5, 1e-6);
  EXPECT_NEAR(lost.reverse_max_distance, 0.0, kFloat);

  const FeatureCoverage none =
      CheckFeatureCoverage(UnitCube(), testing::MakeTorus(12, 8, 2.0, 0.5), 90.5, spacing);
  EXPECT_EQ(none.original_edges, 0u);
  EXPECT_EQ(none.max_distance, 0.0);
}

}  // namespace
}  // namespace femsimp::judge
