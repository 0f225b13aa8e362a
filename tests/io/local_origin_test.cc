// Parts far from the origin are held relative to a local origin (engine/local_origin.h): what a
// file has is kept to the float spacing of the part's own size, not of its distance from the
// origin, and writers put it back where the file had it.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "engine/io/mesh_io.h"
#include "engine/local_origin.h"
#include "engine/mesh.h"
#include "gtest/gtest.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

// A box 8 x 6 x 4 placed some 2 million units from the origin (2^-3 apart as floats there,
// 3 % of the box), its corners at decimals a float cannot hold.
constexpr double kFar[3] = {1000000.0371, 2000000.0813, -300000.0529};

RawMesh FarBox() {
  RawMesh box = testing::MakeBox({8, 6, 4}, {4, 3, 2});
  box.origin = {kFar[0], kFar[1], kFar[2]};
  return box;
}

// The part's own size: what a float relative to its local origin resolves is a fraction of it.
double Diagonal(const RawMesh& m) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t v = 0; v < m.num_vertices(); ++v)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], WorldPoint(m, v)[k]);
      hi[k] = std::max(hi[k], WorldPoint(m, v)[k]);
    }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

// Every vertex where `expected` has it, to 1e-6 of the part: absolute floats there would be off
// by up to 1.6 % of it.
void ExpectSamePlaces(const RawMesh& expected, const RawMesh& got, bool same_order) {
  ASSERT_EQ(got.num_vertices(), expected.num_vertices());
  const double tol = 1e-6 * Diagonal(expected);
  if (same_order) {
    for (size_t v = 0; v < got.num_vertices(); ++v)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(WorldPoint(got, v)[k], WorldPoint(expected, v)[k], tol)
            << "vertex " << v << " coordinate " << k;
    return;
  }
  // STL: per face corner.
  ASSERT_EQ(got.num_faces(), expected.num_faces());
  for (size_t c = 0; c < got.triangles.size(); ++c)
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(WorldPoint(got, got.triangles[c])[k],
                  WorldPoint(expected, expected.triangles[c])[k], tol)
          << "corner " << c << " coordinate " << k;
}

class LocalOriginFormatTest : public testing::FileFormatTest {};

// Written and read back in every format, text and binary: the far box keeps its shape to 1e-6
// of its size, held relative to an origin near it (binary STL holds floats of the absolute
// coordinates: there the file itself rounds, to 2^-3, and only that).
TEST_P(LocalOriginFormatTest, FarPartKeepsItsDetail) {
  const RawMesh in = FarBox();
  const RawMesh out = RoundTrip(in);
  if (GetParam().ext == ".stl" && !GetParam().ascii) {
    ASSERT_EQ(out.num_faces(), in.num_faces());
    for (size_t c = 0; c < out.triangles.size(); ++c)
      for (int k = 0; k < 3; ++k) {
        const double file = static_cast<float>(WorldPoint(in, in.triangles[c])[k]);
        ASSERT_EQ(WorldPoint(out, out.triangles[c])[k], file) << "corner " << c;
      }
  } else {
    ExpectSamePlaces(in, out, GetParam().ext != ".stl");
  }
  EXPECT_FALSE(AtOrigin(out.origin));
  // Relative to its origin the box is held by floats near its own size.
  for (float x : out.positions) EXPECT_LT(std::abs(x), 10.0f);
  EXPECT_TRUE(Mesh::Build(out).ok());
}

// A part near the origin is held as before, at origin 0.
TEST_P(LocalOriginFormatTest, PartNearTheOriginStaysAbsolute) {
  RawMesh in = testing::MakeBox({8, 6, 4}, {4, 3, 2});
  for (size_t i = 0; i < in.positions.size(); ++i) in.positions[i] += (i % 3 == 0) ? 20.0f : 0.0f;
  const RawMesh out = RoundTrip(in);
  EXPECT_TRUE(AtOrigin(out.origin));
  if (GetParam().ext != ".stl") {
    EXPECT_EQ(out.positions, in.positions);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Formats, LocalOriginFormatTest,
    ::testing::Values(testing::FileFormat{".off", true}, testing::FileFormat{".obj", true},
                      testing::FileFormat{".stl", false}, testing::FileFormat{".stl", true},
                      testing::FileFormat{".ply", false}, testing::FileFormat{".ply", true},
                      testing::FileFormat{".msh", true}),
    testing::FileFormatName);

class LocalOriginTest : public testing::TempDirTest {};

// A vertex the simplification leaves where it is goes out as its file wrote it, every digit:
// the writer picks the shortest text that reads back to the same float relative to the origin.
TEST_F(LocalOriginTest, UnmovedVertexIsWrittenAsTheFileHadIt) {
  const std::string off =
      "OFF\n4 4 0\n"
      "1000000.039 2000000.13755 -300000.3481\n"
      "1000001.5 2000000.13755 -300000.3481\n"
      "1000000.039 2000001.25 -300000.3481\n"
      "1000000.039 2000000.13755 -299999.0625\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  absl::StatusOr<RawMesh> in = ReadMeshFile(Write("far.off", off));
  ASSERT_TRUE(in.ok()) << in.status();
  EXPECT_FALSE(AtOrigin(in->origin));
  for (const std::string ext : {".off", ".obj", ".ply"}) {
    ASSERT_TRUE(WriteMeshFileAscii(Path("out" + ext), *in).ok());
    const std::string text = testing::ReadFileBytes(Path("out" + ext));
    EXPECT_NE(text.find("1000000.039 2000000.13755 -300000.3481"), std::string::npos)
        << ext << ":\n"
        << text;
    EXPECT_NE(text.find("1000000.039 2000000.13755 -299999.0625"), std::string::npos) << text;
  }
}

// Binary float files move to the local origin without loss: every coordinate comes back as the
// very float the file holds.
TEST_F(LocalOriginTest, BinaryFloatsMoveExactly) {
  RawMesh box = testing::MakeBox({8, 6, 4}, {4, 3, 2});
  for (size_t i = 0; i < box.positions.size(); ++i)
    box.positions[i] += static_cast<float>(kFar[i % 3]);  // the file's floats, absolute
  ASSERT_TRUE(WriteMeshFile(Path("far.stl"), box).ok());
  absl::StatusOr<RawMesh> read = ReadMeshFile(Path("far.stl"));
  ASSERT_TRUE(read.ok()) << read.status();
  ASSERT_FALSE(AtOrigin(read->origin));
  for (int k = 0; k < 3; ++k)  // a float, so that float minus origin is a float again
    EXPECT_EQ(read->origin[k], double(static_cast<float>(read->origin[k])));
  ASSERT_EQ(read->num_faces(), box.num_faces());
  for (size_t c = 0; c < box.triangles.size(); ++c)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(WorldPoint(*read, read->triangles[c])[k],
                double(box.positions[3 * box.triangles[c] + k]))
          << "corner " << c;
}

// The rule: the origin moves once floats at the part's largest coordinate are coarser than a
// millionth of its size, to the box's centre rounded to floats.
TEST(LocalOriginOf, MovesOnlyWhereFloatsAreCoarseForThePart) {
  const double lo_near[3] = {10, 0, 0}, hi_near[3] = {11, 1, 1};
  EXPECT_TRUE(AtOrigin(LocalOriginOf(lo_near, hi_near)));
  const double lo_far[3] = {100, 0, 0}, hi_far[3] = {101, 1, 1};  // 2^-17 apart: 4.4e-6 of it
  const std::array<double, 3> o = LocalOriginOf(lo_far, hi_far);
  EXPECT_EQ(o[0], 100.5);
  EXPECT_EQ(o[1], 0.5);
  const double lo_point[3] = {1e6, 1e6, 1e6};  // no size: nothing to resolve
  EXPECT_TRUE(AtOrigin(LocalOriginOf(lo_point, lo_point)));
}

}  // namespace
}  // namespace femsimp
