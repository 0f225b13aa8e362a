#include "engine/solid_parts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "engine/mesh.h"
#include "engine/prepare.h"
#include "engine/repair.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

constexpr double kHeight = 2.0;

// A shaft of radius 1 in a bush of radii 1 and 2, both kHeight long, n facets round and m rows
// along the axis (z): an assembly as gmsh's fragment exports it, the cylinder they share listed
// once (facing out of the shaft). The circles where it meets the shaft's end disks and the
// bush's end rings are seams of three faces.
RawMesh ShaftInBush(int n, int m) {
  RawMesh mesh;
  const auto add = [&](double r, double angle, double z) {
    mesh.positions.insert(mesh.positions.end(),
                          {float(r * std::cos(angle)), float(r * std::sin(angle)), float(z)});
    return uint32_t(mesh.num_vertices() - 1);
  };
  std::vector<uint32_t> inner((m + 1) * n), outer((m + 1) * n);
  for (int k = 0; k <= m; ++k)
    for (int i = 0; i < n; ++i) {
      const double angle = 2 * std::numbers::pi * i / n, z = kHeight * k / m;
      inner[k * n + i] = add(1.0, angle, z);
      outer[k * n + i] = add(2.0, angle, z);
    }
  const uint32_t bottom = add(0, 0, 0), top = add(0, 0, kHeight);
  const auto face = [&](uint32_t a, uint32_t b, uint32_t c) {
    mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
  };
  const auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    face(a, b, c);
    face(a, c, d);
  };
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    for (int k = 0; k < m; ++k) {
      quad(inner[k * n + i], inner[k * n + j], inner[(k + 1) * n + j], inner[(k + 1) * n + i]);
      quad(outer[k * n + i], outer[k * n + j], outer[(k + 1) * n + j], outer[(k + 1) * n + i]);
    }
    face(bottom, inner[j], inner[i]);
    face(top, inner[m * n + i], inner[m * n + j]);
    quad(inner[i], inner[j], outer[j], outer[i]);
    quad(inner[m * n + i], outer[m * n + i], outer[m * n + j], inner[m * n + j]);
  }
  return mesh;
}

double PolygonArea(int n, double r) { return 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n); }

DVec3 At(const RawMesh& m, uint32_t v) {
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

// The shaft's and the bush's volumes of a ShaftInBush soup, told apart by where the faces lie
// rather than by the regions FindSolidParts finds: the shaft is bounded by the faces within
// radius 1 (its end disks and the shared cylinder, which faces out of it), the bush by the
// others and that cylinder turned.
std::pair<double, double> ShaftAndBushByRadius(const RawMesh& m) {
  double shaft = 0, bush = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const DVec3 a = At(m, m.triangles[3 * f]), b = At(m, m.triangles[3 * f + 1]),
                c = At(m, m.triangles[3 * f + 2]);
    const double volume = Dot(a, Cross(b, c)) / 6.0;
    double r = 0;
    for (const DVec3& p : {a, b, c}) r = std::max(r, std::hypot(p.x, p.y));
    const bool wall = std::fabs(a.z - b.z) + std::fabs(a.z - c.z) > 0 && r < 1.0 + 1e-5;
    if (r < 1.0 + 1e-5) shaft += volume;
    if (r > 1.0 + 1e-5) bush += volume;
    if (wall) bush -= volume;
  }
  return {shaft, bush};
}

TEST(SolidParts, ShaftInBushIsTwoParts) {
  const int n = 32;
  const RawMesh mesh = ShaftInBush(n, 4);
  const SolidParts parts = FindSolidParts(mesh);
  ASSERT_EQ(parts.parts(), 2u);
  ASSERT_EQ(parts.face_sides.size(), mesh.num_faces());
  // The first face is on the shared cylinder: the shaft behind it, the bush ahead.
  const FaceSides& wall = parts.sides[parts.face_sides[0]];
  EXPECT_EQ(wall.weight, 0);
  ASSERT_NE(wall.behind, kSpace);
  ASSERT_NE(wall.ahead, kSpace);
  const double shaft = PolygonArea(n, 1) * kHeight;
  const double bush = (PolygonArea(n, 2) - PolygonArea(n, 1)) * kHeight;
  EXPECT_NEAR(parts.volumes[wall.behind], shaft, 1e-6 * shaft);
  EXPECT_NEAR(parts.volumes[wall.ahead], bush, 1e-6 * bush);
  // Every other face bounds one part and faces out of it.
  size_t walls = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const FaceSides& s = parts.sides[parts.face_sides[f]];
    if (s == wall) {
      ++walls;
      continue;
    }
    EXPECT_EQ(s.weight, 1) << "face " << f;
    EXPECT_EQ(s.ahead, kSpace) << "face " << f;
  }
  EXPECT_EQ(walls, size_t{2 * n * 4});
}

TEST(SolidParts, BoxesTouchingAlongAnEdgeAreTwoParts) {
  RawMesh mesh = testing::MakeBox({1, 1, 1}, {2, 2, 2});
  testing::Append(mesh, testing::MakeBox({1, 1, 1}, {2, 2, 2}), {1, 1, 0});
  ASSERT_TRUE(RepairMesh(mesh, RepairOptions{}).ok());  // welds the shared edge's points
  const SolidParts parts = FindSolidParts(mesh);
  ASSERT_EQ(parts.parts(), 2u);
  EXPECT_NEAR(parts.volumes[0], 1.0, 1e-9);
  EXPECT_NEAR(parts.volumes[1], 1.0, 1e-9);
  for (const FaceSides& s : parts.sides) EXPECT_EQ(s.weight, 1);
}

TEST(SolidParts, NoneWithoutSeamsOrWhereSpaceReachesInside) {
  EXPECT_EQ(FindSolidParts(testing::MakeBox({1, 2, 3}, {2, 2, 2})).parts(), 0u);
  RawMesh open = ShaftInBush(16, 2);
  open.triangles.resize(open.triangles.size() - 3);  // a facet of the top ring missing
  const SolidParts none = FindSolidParts(open);
  EXPECT_EQ(none.parts(), 0u);
  EXPECT_TRUE(none.sides.empty());
}

// Three flat sheets on one square border: seams, but no volume anywhere.
TEST(SolidParts, NoneInFlatSheets) {
  RawMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 0, 0.25f, 0.5f, 0};
  m.triangles = {0, 1, 2, 0, 2, 3,                     // the square in two
                 1, 0, 4, 2, 1, 4, 3, 2, 4, 0, 3, 4,   // a fan, facing down
                 0, 1, 5, 1, 2, 5, 2, 3, 5, 3, 0, 5};  // another, facing up
  const SolidParts parts = FindSolidParts(m);
  EXPECT_EQ(parts.parts(), 0u);
  EXPECT_TRUE(parts.sides.empty());
}

TEST(SolidParts, ASeparateBodyKeepsItsOrientation) {
  RawMesh mesh = ShaftInBush(16, 2);
  const size_t assembly_faces = mesh.num_faces();
  testing::Append(mesh, testing::MakeBox({1, 1, 1}, {1, 1, 1}), {5, 0, 0});
  const SolidParts parts = FindSolidParts(mesh);
  ASSERT_EQ(parts.parts(), 2u);
  for (size_t f = assembly_faces; f < mesh.num_faces(); ++f)
    EXPECT_EQ(parts.sides[parts.face_sides[f]], (FaceSides{kSpace, kSpace, 1})) << "face " << f;
}

TEST(SolidParts, MeshBuildTakesThemIntoTheFlags) {
  RawMesh m = testing::Tetrahedron();
  m.sides = {FaceSides{}, FaceSides{0, kSpace, 1}};
  m.face_sides = {1, 1, 1};
  EXPECT_FALSE(Mesh::Build(m).ok());  // one per face
  m.face_sides = {1, 1, 1, 2};
  EXPECT_FALSE(Mesh::Build(m).ok());  // out of range
  m.face_sides = {1, 1, 1, 1};
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_EQ(mesh->sides(), m.sides);
  for (uint32_t h = 0; h < mesh->halfedge_capacity(); ++h)
    EXPECT_EQ(Mesh::SidesOf(mesh->halfedges()[h]), 1u);
  // Faces joined across an edge must see the same parts, or the mesh has none.
  m.face_sides = {1, 1, 1, 0};
  mesh = Mesh::Build(m);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_TRUE(mesh->sides().empty());
  for (uint32_t h = 0; h < mesh->halfedge_capacity(); ++h)
    EXPECT_EQ(Mesh::SidesOf(mesh->halfedges()[h]), 0u);
}

struct AssemblyRun {
  SimplifyResult result;
  RawMesh output;
};

AssemblyRun SimplifyAssembly(const RawMesh& input, const SimplifyOptions& options) {
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(input, RepairOptions{});
  EXPECT_TRUE(prepared.ok()) << prepared.status();
  if (!prepared.ok()) return {};
  EXPECT_FALSE(prepared->mesh.sides().empty());
  absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, options);
  EXPECT_TRUE(result.ok()) << result.status();
  absl::StatusOr<RawMesh> output =
      OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
  EXPECT_TRUE(output.ok()) << output.status();
  if (!result.ok() || !output.ok()) return {};
  return {*result, *output};
}

// The volume budget holds each part of an assembly, not only their sum: the bush's and the
// shaft's volumes from the output soup (told apart by radius) stay within it, and are what the
// result reports. Without the budget the shaft's facets coarsen past it.
TEST(SolidParts, EachPartKeepsItsVolumeWithinTheBudget) {
  const RawMesh input = ShaftInBush(96, 3);
  const auto [shaft_in, bush_in] = ShaftAndBushByRadius(input);
  for (const double budget : {0.005, 0.001, 0.0}) {
    SimplifyOptions options;  // the plain call's defaults, the budget aside
    options.max_volume_change = budget;
    const AssemblyRun run = SimplifyAssembly(input, options);
    ASSERT_EQ(run.result.parts.size(), 2u) << budget;
    const auto [shaft_out, bush_out] = ShaftAndBushByRadius(run.output);
    const double shaft_change = shaft_out / shaft_in - 1, bush_change = bush_out / bush_in - 1;
    std::printf("budget %g: %zu -> %zu vertices, shaft %+.4f%%, bush %+.4f%%\n", budget,
                input.num_vertices(), run.output.num_vertices(), 100 * shaft_change,
                100 * bush_change);
    EXPECT_LT(run.output.num_vertices() * 4, input.num_vertices() * 3);
    // The result's parts are these two (the shaft is the smaller).
    const auto& [small, large] = run.result.parts[0].input < run.result.parts[1].input
                                     ? std::pair(run.result.parts[0], run.result.parts[1])
                                     : std::pair(run.result.parts[1], run.result.parts[0]);
    EXPECT_NEAR(small.input, shaft_in, 1e-9 * shaft_in);
    EXPECT_NEAR(large.input, bush_in, 1e-9 * bush_in);
    EXPECT_NEAR(small.output, shaft_out, 1e-9 * shaft_in);
    EXPECT_NEAR(large.output, bush_out, 1e-9 * bush_in);
    EXPECT_NEAR(run.result.output_mass.measure, shaft_out + bush_out, 1e-9 * bush_in);
    if (budget > 0) {
      EXPECT_LE(std::fabs(shaft_change), budget);
      EXPECT_LE(std::fabs(bush_change), budget);
    } else {
      EXPECT_GT(std::fabs(shaft_change), 0.005);
    }
  }
}

}  // namespace
}  // namespace femsimp
