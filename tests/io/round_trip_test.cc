// Write then read back every format, on a hand-made tetrahedron and on fandisk.off.
#include <cmath>
#include <string>

#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "gtest/gtest.h"
#include "tests/io/test_files.h"

namespace femsimp {
namespace {

using testing::TempDirTest;

struct Variant {
  std::string ext;
  bool ascii;
};

std::string VariantName(const ::testing::TestParamInfo<Variant>& info) {
  return info.param.ext.substr(1) + (info.param.ascii ? "_ascii" : "_binary");
}

class RoundTripTest : public TempDirTest, public ::testing::WithParamInterface<Variant> {
 protected:
  RawMesh RoundTrip(const RawMesh& in) {
    const std::string path = Path("mesh" + GetParam().ext);
    absl::Status written =
        GetParam().ascii ? WriteMeshFileAscii(path, in) : WriteMeshFile(path, in);
    EXPECT_TRUE(written.ok()) << written;
    absl::StatusOr<RawMesh> out = ReadMeshFile(path);
    EXPECT_TRUE(out.ok()) << out.status();
    return out.ok() ? *out : RawMesh{};
  }

  // OFF, OBJ and PLY keep vertex and face order and (at 9 digits or in binary) every bit.
  // STL stores corners per facet; OpenMesh merges equal points again in order of first use,
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
  const RawMesh in = testing::Tetrahedron();
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

INSTANTIATE_TEST_SUITE_P(Formats, RoundTripTest,
                         ::testing::Values(Variant{".off", true}, Variant{".obj", true},
                                           Variant{".stl", false}, Variant{".stl", true},
                                           Variant{".ply", false}, Variant{".ply", true}),
                         VariantName);

class WriteTest : public TempDirTest {};

TEST_F(WriteTest, UpperCaseExtensionPicksTheFormat) {
  for (const char* name : {"MESH.OFF", "Mesh.Obj", "MESH.STL", "MESH.PLY"}) {
    const std::string path = Path(name);
    ASSERT_TRUE(WriteMeshFile(path, testing::Tetrahedron()).ok()) << name;
    absl::StatusOr<RawMesh> out = ReadMeshFile(path);
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(out->num_vertices(), 4u) << name;
    EXPECT_EQ(out->num_faces(), 4u) << name;
  }
}

TEST_F(WriteTest, MissingDirectory) {
  absl::Status s = WriteMeshFile(Path("no/such/dir/mesh.off"), testing::Tetrahedron());
  EXPECT_EQ(s.code(), absl::StatusCode::kNotFound);
  EXPECT_NE(s.message().find("does not exist"), std::string::npos) << s;
}

TEST_F(WriteTest, UnknownExtension) {
  absl::Status s = WriteMeshFile(Path("mesh.vtk"), testing::Tetrahedron());
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("'.vtk' (supported: .off, .obj, .stl, .ply)"), std::string::npos) << s;
}

TEST_F(WriteTest, NonManifoldSoupIsRefused) {
  RawMesh in = testing::Tetrahedron();
  in.triangles.insert(in.triangles.end(), {0, 2, 1});  // a second copy of face 0
  absl::Status s = WriteMeshFile(Path("bad.off"), in);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("face 4"), std::string::npos) << s;
}

}  // namespace
}  // namespace femsimp
