// Polygons in mesh files are cut into triangles on reading (engine/io/polygons.h).
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/io/mesh_readers.h"
#include "engine/io/polygons.h"
#include "gtest/gtest.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

ParsedMeshFile Parse(const std::string& ext, const std::string& data) {
  absl::StatusOr<ParsedMeshFile> parsed = ParseMeshFile(ext, data);
  EXPECT_TRUE(parsed.ok()) << parsed.status();
  return parsed.ok() ? *std::move(parsed) : ParsedMeshFile{};
}

// Twice the signed area of triangle f projected on z.
double TwiceAreaZ(const RawMesh& m, size_t f) {
  const float* a = &m.positions[3 * size_t(m.triangles[3 * f])];
  const float* b = &m.positions[3 * size_t(m.triangles[3 * f + 1])];
  const float* c = &m.positions[3 * size_t(m.triangles[3 * f + 2])];
  return double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]);
}

constexpr char kCubeVertices[] = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";

// A cube of six quads, outward: the same closed solid from OBJ, OFF (text and binary), PLY and MSH.
TEST(Polygons, QuadCubeInEveryFormatWithPolygons) {
  const std::string quads[6] = {"0 3 2 1", "4 5 6 7", "0 1 5 4", "1 2 6 5", "2 3 7 6", "3 0 4 7"};
  std::string obj, off = "OFF\n8 6 0\n" + std::string(kCubeVertices), ply;
  for (const char* line : {"0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1"})
    absl::StrAppend(&obj, "v ", line, "\n");
  for (const std::string& q : quads) {
    obj += "f";
    for (const char c : q)
      if (c != ' ') absl::StrAppend(&obj, " ", c - '0' + 1);
    obj += "\n";
    off += "4 " + q + "\n";
  }
  ply =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 6\nproperty list uchar int vertex_indices\n"
      "end_header\n" +
      std::string(kCubeVertices);
  for (const std::string& q : quads) ply += "4 " + q + "\n";
  // gmsh's recombined surfaces: 4-node quadrangles (element type 3), physical group 5.
  std::string msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n";
  for (int i = 0; i < 8; ++i)
    absl::StrAppend(&msh, i + 1, " ", i & 1 ? 1 : 0, " ", (i >> 1) & 1 ? 1 : 0, " ", i >> 2, "\n");
  msh += "$EndNodes\n$Elements\n6\n";
  // The same quads on nodes numbered by their bits (x + 2y + 4z) + 1.
  const int by_bits[8] = {1, 2, 4, 3, 5, 6, 8, 7};  // the cube's corner i above is node by_bits[i]
  for (int q = 0; q < 6; ++q) {
    absl::StrAppend(&msh, q + 1, " 3 2 5 1");
    for (const char c : quads[q])
      if (c != ' ') absl::StrAppend(&msh, " ", by_bits[c - '0']);
    msh += "\n";
  }
  msh += "$EndElements\n";
  // Binary OFF (little-endian, as OpenMesh writes it): counts, floats, then per face its corner
  // count and corners.
  std::string binary = "OFF BINARY\n";
  const auto put = [&binary](auto x) {
    binary.append(reinterpret_cast<const char*>(&x), sizeof x);
  };
  for (const int32_t n : {8, 6, 0}) put(n);
  for (int i = 0; i < 8; ++i)
    for (const float x : {float(i == 1 || i == 2 || i == 5 || i == 6),
                          float(i == 2 || i == 3 || i == 6 || i == 7), float(i >= 4)})
      put(x);
  for (const std::string& q : quads) {
    put(int32_t{4});
    for (const char c : q)
      if (c != ' ') put(int32_t(c - '0'));
  }
  for (const auto& [ext, data] :
       {std::pair{".obj", obj}, {".off", off}, {".off", binary}, {".ply", ply}, {".msh", msh}}) {
    SCOPED_TRACE(ext);
    const ParsedMeshFile file = Parse(ext, data);
    EXPECT_EQ(file.mesh.num_faces(), 12u);
    EXPECT_NEAR(testing::SignedVolume(file.mesh), 1.0,
                1e-12);  // every triangle keeps its quad's winding
    ASSERT_EQ(file.warnings.size(), 1u);
    EXPECT_EQ(
        file.warnings[0],
        std::string(ext == std::string(".msh") ? "msh: " : "") +
            "polygons: cut 6 polygons (up to 4 corners) into 12 triangles; facet numbers from "
            "here on count these triangles");
  }
}

// An L-shaped hexagon (not convex): its triangles cover it once, none outside, none folded.
TEST(Polygons, NonConvexPolygonIsCoveredOnce) {
  const ParsedMeshFile file =
      Parse(".off", "OFF\n6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 0 1 2 3 4 5\n");
  ASSERT_EQ(file.mesh.num_faces(), 4u);
  double sum = 0;
  for (size_t f = 0; f < 4; ++f) {
    const double a = TwiceAreaZ(file.mesh, f);
    EXPECT_GT(a, 0) << "triangle " << f;
    sum += a;
  }
  EXPECT_NEAR(sum / 2, 3.0, 1e-12);
  // The reflex corner (3) is in a triangle, so no triangle spans the notch: each uses corner 3
  // or lies on one side of it.
  for (size_t f = 0; f < 4; ++f) {
    const std::set<uint32_t> t(&file.mesh.triangles[3 * f], &file.mesh.triangles[3 * f] + 3);
    EXPECT_FALSE(t == std::set<uint32_t>({2, 4, 0}) || t == std::set<uint32_t>({1, 2, 4}))
        << "triangle " << f << " crosses the notch";
  }
}

// A long parallelogram: cut along its short diagonal, which keeps the triangles' angles larger.
TEST(Polygons, QuadIsCutAlongTheDiagonalOfTheBetterTriangles) {
  const ParsedMeshFile file = Parse(".obj", "v 0 0 0\nv 10 0 0\nv 11 1 0\nv 1 1 0\nf 1 2 3 4\n");
  ASSERT_EQ(file.mesh.num_faces(), 2u);
  for (size_t f = 0; f < 2; ++f) {
    const std::set<uint32_t> t(&file.mesh.triangles[3 * f], &file.mesh.triangles[3 * f] + 3);
    EXPECT_TRUE(t.count(1) && t.count(3)) << "triangle " << f << " does not use edge 1-3";
  }
}

// A polygon's group, fields and line go with each of its triangles, and faces after it keep
// theirs; a corner beyond the file's vertices is refused by face and line.
TEST(Polygons, GroupsFieldsAndLinesFollow) {
  const ParsedMeshFile obj = Parse(".obj",
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
                                   "g top\nf 1 2 3 4\ng side\nf 2 5 3\n");
  ASSERT_EQ(obj.mesh.num_faces(), 3u);
  ASSERT_EQ(obj.mesh.face_groups.size(), 3u);
  EXPECT_EQ(obj.mesh.face_groups[0], obj.mesh.face_groups[1]);
  EXPECT_NE(obj.mesh.face_groups[1], obj.mesh.face_groups[2]);
  EXPECT_EQ(std::vector<uint32_t>(obj.mesh.triangles.begin() + 6, obj.mesh.triangles.end()),
            (std::vector<uint32_t>{1, 4, 2}));

  const ParsedMeshFile ply =
      Parse(".ply",
            "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
            "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
            "property int group\nproperty float pressure\nend_header\n"
            "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3 7 2.5\n3 1 4 2 9 4.5\n");
  ASSERT_EQ(ply.mesh.num_faces(), 3u);
  EXPECT_EQ(ply.mesh.face_groups, (std::vector<uint32_t>{7, 7, 9}));
  ASSERT_EQ(ply.mesh.face_fields.size(), 1u);
  EXPECT_EQ(ply.mesh.face_fields[0].values, (std::vector<float>{2.5f, 2.5f, 4.5f}));

  absl::StatusOr<ParsedMeshFile> bad =
      ParseMeshFile(".obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n\nf 1 2 3 9\n");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().message(),
            "face 1 (line 6) references vertex 8 but the file has 3 vertices");
}

}  // namespace
}  // namespace femsimp
