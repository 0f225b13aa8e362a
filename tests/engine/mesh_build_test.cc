#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/mesh.h"
#include "engine/mesh_checks.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::Octahedron;

void ExpectRejected(const RawMesh& raw, const std::string& needle) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_FALSE(mesh.ok()) << "accepted a mesh that should fail with: " << needle;
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(mesh.status().message().find(needle), std::string::npos) << mesh.status();
}

TEST(MeshBuild, AcceptsClosedAndOpenMeshes) {
  ASSERT_TRUE(Mesh::Build(Octahedron()).ok());
  absl::StatusOr<Mesh> grid = Mesh::Build(testing::FlatGrid(3));
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->CountLiveVertices(), 16u);
  EXPECT_EQ(grid->CountLiveFaces(), 18u);
}

// Point ids name copies of one point (seam copies): one per vertex, and copies where they are.
TEST(MeshBuild, PointIdsAreCheckedAndKept) {
  RawMesh raw = testing::SingleTriangle();
  // A second sheet whose vertex 3 copies vertex 1.
  raw.positions.insert(raw.positions.end(), {1, 0, 0, 1, 1, 0, 2, 1, 0});
  raw.triangles.insert(raw.triangles.end(), {3, 4, 5});
  raw.point_ids = {0, 1, 2, 1, 4, 5};
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  ASSERT_NE(mesh->point_ids(), nullptr);
  EXPECT_EQ(mesh->point_ids()[3], 1u);
  EXPECT_EQ(Mesh::Build(testing::SingleTriangle())->point_ids(), nullptr);

  RawMesh moved = raw;
  moved.positions[3 * 3] = 1.5f;
  ExpectRejected(moved, "vertices 1 and 3 share point id 1 but lie at (1, 0, 0) and (1.5, 0, 0)");
  RawMesh short_list = raw;
  short_list.point_ids.pop_back();
  ExpectRejected(short_list, "point ids: 5 for 6 vertices");
}

TEST(MeshBuild, RejectsEmpty) {
  ExpectRejected(RawMesh{}, "empty");
  RawMesh no_faces = Octahedron();
  no_faces.triangles.clear();
  ExpectRejected(no_faces, "empty");
}

TEST(MeshBuild, RejectsNonFiniteCoordinates) {
  RawMesh m = Octahedron();
  m.positions[4] = std::numeric_limits<float>::quiet_NaN();
  ExpectRejected(m, "vertex 1 has a non-finite coordinate");
  m.positions[4] = std::numeric_limits<float>::infinity();
  ExpectRejected(m, "vertex 1 has a non-finite coordinate");
}

TEST(MeshBuild, RejectsIndexOutOfRange) {
  RawMesh m = Octahedron();
  m.triangles[7] = 99;
  ExpectRejected(m, "face 2 references vertex 99 but the mesh has 6 vertices");
}

TEST(MeshBuild, RejectsDegenerateFaces) {
  RawMesh m = Octahedron();
  m.triangles[1] = m.triangles[0];
  ExpectRejected(m, "face 0 is degenerate");
  RawMesh flat = testing::SingleTriangle();
  flat.positions[6] = 2;  // third vertex on the line through the first two
  flat.positions[7] = 0;
  ExpectRejected(flat, "zero area");
}

TEST(MeshBuild, RejectsDuplicateFaces) {
  RawMesh same = testing::SingleTriangle();
  same.triangles.insert(same.triangles.end(), {0, 1, 2});
  ExpectRejected(same, "same direction");
  RawMesh flipped = testing::SingleTriangle();
  flipped.triangles.insert(flipped.triangles.end(), {0, 2, 1});
  ExpectRejected(flipped, "duplicates");
}

TEST(MeshBuild, RejectsNonManifoldEdge) {
  RawMesh m = {{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1}, {0, 1, 2, 1, 0, 3, 0, 1, 4}, {}, {}};
  ExpectRejected(m, "non-manifold edge (0, 1): shared by 3 faces");
}

TEST(MeshBuild, RejectsNonManifoldVertex) {
  // Two triangles touching only at vertex 0.
  RawMesh m = {{0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0}, {0, 1, 2, 0, 3, 4}, {}, {}};
  ExpectRejected(m, "vertex 0 is non-manifold");
}

TEST(MeshBuild, RejectsInconsistentOrientation) {
  RawMesh m = Octahedron();
  std::swap(m.triangles[0], m.triangles[1]);  // flip face 0
  ExpectRejected(m, "inconsistent orientation");
}

TEST(MeshBuild, DropsIsolatedVertices) {
  RawMesh m = Octahedron();
  m.positions.insert(m.positions.end(), {5, 5, 5});
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_EQ(mesh->CountLiveVertices(), 6u);
  EXPECT_EQ(mesh->ToRaw().num_vertices(), 6u);
}

TEST(MeshBuild, RoundTripKeepsFacesAndGroups) {
  RawMesh m = Octahedron();
  m.face_groups = {1, 1, 1, 1, 2, 2, 2, 2};
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  ASSERT_TRUE(mesh.ok());
  const RawMesh back = mesh->ToRaw();
  EXPECT_EQ(back.positions, m.positions);
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_EQ(back.face_groups, m.face_groups);
}

// The output check of femsimp-load --verify (engine/mesh_checks.h).
TEST(OutputCheck, TopologyOfATorusAndWhatBreaksIt) {
  const RawMesh torus = testing::MakeTorus(12, 10);
  const SoupTopology t = TopologyOf(torus);
  EXPECT_EQ(t.vertices, 120);
  EXPECT_EQ(t.faces, 240);
  EXPECT_EQ(t.edges, 360);
  EXPECT_EQ(t.euler(), 0);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_TRUE(CheckOutput(t, torus).ok());

  RawMesh open = torus;  // one face less: no longer closed, Euler characteristic -1
  open.triangles.resize(open.triangles.size() - 3);
  absl::Status s = CheckOutput(t, open);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("Euler"), std::string_view::npos) << s;

  RawMesh two = torus;  // a second, disjoint torus: larger, and two components
  RawMesh other = testing::MakeTorus(12, 10);
  for (uint32_t& i : other.triangles) i += 120;
  two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
  two.triangles.insert(two.triangles.end(), other.triangles.begin(), other.triangles.end());
  EXPECT_FALSE(CheckOutput(t, two).ok());

  RawMesh degenerate = torus;  // a face using one vertex twice
  degenerate.triangles[2] = degenerate.triangles[1];
  EXPECT_FALSE(CheckOutput(t, degenerate).ok());
}

}  // namespace
}  // namespace femsimp
