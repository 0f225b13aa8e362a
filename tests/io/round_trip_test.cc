// Write then read back every format, on a hand-made tetrahedron and on fandisk.off.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/str_format.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "gtest/gtest.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::TempDirTest;

class RoundTripTest : public testing::FileFormatTest {
 protected:
  // OFF, OBJ and PLY keep vertex and face order and (at 9 digits or in binary) every bit.
  // STL stores corners per facet; the reader joins equal points again in order of first use,
  // so compare the corners of each face.
  void ExpectSame(const RawMesh& in, const RawMesh& out) {
    ASSERT_EQ(out.num_vertices(), in.num_vertices());
    ASSERT_EQ(out.num_faces(), in.num_faces());
    if (GetParam().ext != ".stl") {
      EXPECT_EQ(out.positions, in.positions);
      EXPECT_EQ(out.triangles, in.triangles);
    } else {
      for (size_t c = 0; c < in.triangles.size(); ++c)
        for (int i = 0; i < 3; ++i) {
          const float a = in.positions[3 * in.triangles[c] + i];
          const float b = out.positions[3 * out.triangles[c] + i];
          ASSERT_NEAR(b, a, 4 * std::numeric_limits<float>::epsilon() * std::max(1.0f, std::abs(a)))
              << "corner " << c << " coordinate " << i;
        }
    }
    absl::StatusOr<Mesh> mesh = Mesh::Build(out);
    EXPECT_TRUE(mesh.ok()) << mesh.status();
  }
};

TEST_P(RoundTripTest, Tetrahedron) {
  const RawMesh in = testing::PreciseTetrahedron();
  ASSERT_TRUE(Mesh::Build(in).ok());
  ExpectSame(in, RoundTrip(in));
}

TEST_P(RoundTripTest, Fandisk) {
  absl::StatusOr<RawMesh> in = ReadMeshFile(testing::TestDataPath("fandisk.off"));
  ASSERT_TRUE(in.ok()) << in.status();
  EXPECT_EQ(in->num_vertices(), 6475u);
  EXPECT_EQ(in->num_faces(), 12946u);
  ASSERT_TRUE(Mesh::Build(*in).ok());
  ExpectSame(*in, RoundTrip(*in));
}

INSTANTIATE_TEST_SUITE_P(
    Formats, RoundTripTest,
    ::testing::Values(testing::FileFormat{".off", true}, testing::FileFormat{".obj", true},
                      testing::FileFormat{".stl", false}, testing::FileFormat{".stl", true},
                      testing::FileFormat{".ply", false}, testing::FileFormat{".ply", true},
                      testing::FileFormat{".msh", true}),
    testing::FileFormatName);

class WriteTest : public TempDirTest {};

// The soup renumbered so that vertices come in order of first use by the faces.
RawMesh InOrderOfFirstUse(const RawMesh& in) {
  RawMesh out;
  std::vector<uint32_t> index(in.num_vertices(), ~0u);
  for (uint32_t v : in.triangles) {
    if (index[v] == ~0u) {
      index[v] = uint32_t(out.num_vertices());
      out.positions.insert(out.positions.end(), &in.positions[3 * v], &in.positions[3 * v + 3]);
    }
    out.triangles.push_back(index[v]);
  }
  return out;
}

// ASCII STL with every float written exactly.
std::string StlText(const RawMesh& m) {
  std::ostringstream s;
  s.precision(9);
  s << "solid m\n";
  for (size_t f = 0; f < m.num_faces(); ++f) {
    s << "facet normal 0 0 0\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
      const float* p = &m.positions[3 * m.triangles[3 * f + k]];
      s << "vertex " << p[0] << " " << p[1] << " " << p[2] << "\n";
    }
    s << "endloop\nendfacet\n";
  }
  return s.str() + "endsolid m\n";
}

// STL has no shared vertices: the reader joins exactly equal corners into one vertex, numbered
// in order of first appearance (as OpenMesh's STL reader did). An OFF file whose vertices come in
// that order therefore reads as the very same mesh, from binary and from ASCII STL.
TEST_F(WriteTest, StlReadsAsTheEquivalentOff) {
  const RawMesh mesh = InOrderOfFirstUse(testing::LoadTestMesh("fandisk.off"));
  ASSERT_TRUE(WriteMeshFileAscii(Path("m.off"), mesh).ok());
  ASSERT_TRUE(WriteMeshFile(Path("m.stl"), mesh).ok());
  absl::StatusOr<RawMesh> off = ReadMeshFile(Path("m.off"));
  ASSERT_TRUE(off.ok()) << off.status();
  for (const std::string& stl : {Path("m.stl"), Write("a.stl", StlText(mesh))}) {
    absl::StatusOr<RawMesh> read = ReadMeshFile(stl);
    ASSERT_TRUE(read.ok()) << read.status();
    EXPECT_EQ(read->positions, off->positions) << stl;
    EXPECT_EQ(read->triangles, off->triangles) << stl;
  }
}

// 0 and -0 are the same point: two facets that share an edge, once written with -0.
TEST_F(WriteTest, StlJoinsZeroAndNegativeZero) {
  absl::StatusOr<RawMesh> m = ReadMeshFile(Write("z.stl",
                                                 "solid z\nouter loop\nvertex 0 0 0\n"
                                                 "vertex 1 0 0\nvertex 0 1 0\nendloop\n"
                                                 "outer loop\nvertex 1 -0 0\nvertex 1 1 0\n"
                                                 "vertex -0 1 -0\nendloop\nendsolid z\n"));
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->num_vertices(), 4u);
  EXPECT_EQ(m->triangles, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(m->positions[3], 1.0f);
  EXPECT_FALSE(std::signbit(m->positions[4]));  // the first appearance gives the coordinates
}

TEST_F(WriteTest, UpperCaseExtensionPicksTheFormat) {
  for (const char* name : {"MESH.OFF", "Mesh.Obj", "MESH.STL", "MESH.PLY"}) {
    const std::string path = Path(name);
    ASSERT_TRUE(WriteMeshFile(path, testing::PreciseTetrahedron()).ok()) << name;
    absl::StatusOr<RawMesh> out = ReadMeshFile(path);
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(out->num_vertices(), 4u) << name;
    EXPECT_EQ(out->num_faces(), 4u) << name;
  }
}

TEST_F(WriteTest, MissingDirectory) {
  absl::Status s = WriteMeshFile(Path("no/such/dir/mesh.off"), testing::PreciseTetrahedron());
  EXPECT_EQ(s.code(), absl::StatusCode::kNotFound);
  EXPECT_NE(s.message().find("does not exist"), std::string::npos) << s;
}

TEST_F(WriteTest, UnknownExtension) {
  absl::Status s = WriteMeshFile(Path("mesh.vtk"), testing::PreciseTetrahedron());
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("'.vtk' (supported: .off, .obj, .stl, .ply, .msh)"), std::string::npos)
      << s;
}

// What other tools write in OBJ: a fourth (w) coordinate, texture and normal indices, relative
// indices, objects, materials, smoothing groups and a face continued over lines.
TEST_F(WriteTest, ObjStatementsOfOtherToolsReadAsTheTetrahedron) {
  const RawMesh tet = testing::PreciseTetrahedron();
  std::string text = "# exported\nmtllib part.mtl\no part\n";
  for (size_t v = 0; v < tet.num_vertices(); ++v)
    text += absl::StrFormat("v %.9g %.9g %.9g 1.0\n", tet.positions[3 * v],
                            tet.positions[3 * v + 1], tet.positions[3 * v + 2]);
  text += "vt 0 0\nvn 0 0 1\nusemtl steel\ns off\n";
  const uint32_t* t = tet.triangles.data();
  text += absl::StrFormat("f %d/1/1 %d/1/1 %d/1/1\n", t[0] + 1, t[1] + 1, t[2] + 1);
  text += absl::StrFormat("f %d//1 %d//1 %d//1\n", int(t[3]) - 4, int(t[4]) - 4, int(t[5]) - 4);
  text += absl::StrFormat("f %d \\\n  %d \\  \n%d\n", t[6] + 1, t[7] + 1, t[8] + 1);
  text += absl::StrFormat("f %d/1 %d/1 %d/1\n", t[9] + 1, t[10] + 1, t[11] + 1);
  absl::StatusOr<RawMesh> back = ReadMeshFile(Write("tools.obj", text));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->triangles, tet.triangles);
  EXPECT_EQ(back->positions, tet.positions);
}

// The output of an assembly keeps its seams (an edge of three faces): every format writes it as
// it is, and reads it back the same.
TEST_F(WriteTest, SeamOfThreeFacesIsWrittenAsItIs) {
  RawMesh hinge;
  hinge.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  hinge.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  for (const char* name : {"hinge.off", "hinge.obj", "hinge.ply"}) {
    ASSERT_TRUE(WriteMeshFile(Path(name), hinge).ok()) << name;
    absl::StatusOr<RawMesh> back = ReadMeshFile(Path(name));
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(back->triangles, hinge.triangles) << name;
    EXPECT_EQ(back->positions, hinge.positions) << name;
  }
  ASSERT_TRUE(WriteMeshFile(Path("hinge.stl"), hinge).ok());
  absl::StatusOr<RawMesh> stl = ReadMeshFile(Path("hinge.stl"));
  ASSERT_TRUE(stl.ok()) << stl.status();
  EXPECT_EQ(stl->num_faces(), 3u);
  EXPECT_EQ(stl->num_vertices(), 5u);  // corners welded back by their coordinates
}

}  // namespace
}  // namespace femsimp
