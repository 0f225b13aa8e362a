// The readers' fast paths (issue 14, item 2) give what the general ones gave: a file that is not
// a regular file is read to its end instead of mapped; binary PLY records read in place, with
// any record they do not take refused by the general loop in its words; STL corners welded
// however far apart their facets are, the index growing past its first guess; text numbers at
// the ends of the float range.
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/io/mesh_io.h"
#include "gtest/gtest.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

class FastPathTest : public testing::TempDirTest {
 protected:
  // The error of reading `path`; fails the test when the file is accepted.
  std::string ReadError(const std::string& path) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    EXPECT_FALSE(m.ok()) << path << " was accepted";
    if (m.ok()) return "";
    EXPECT_EQ(m.status().code(), absl::StatusCode::kInvalidArgument) << m.status();
    return std::string(m.status().message());
  }
};

// Little-endian bytes of values, appended.
struct Bytes {
  std::string s;
  template <typename T>
  Bytes& operator<<(T v) {
    auto b = std::bit_cast<std::array<char, sizeof(T)>>(v);
    if constexpr (std::endian::native == std::endian::big) std::reverse(b.begin(), b.end());
    s.append(b.data(), b.size());
    return *this;
  }
};

constexpr char kPlyTetHeader[] =
    "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
    "property float y\nproperty float z\nelement face 4\n"
    "property list uchar int vertex_indices\nproperty int group\nproperty float load\n"
    "end_header\n";

// The tetrahedron as binary PLY with a group and a field per face; `face` lets a test spoil
// one face's record (count, corners, group, load).
std::string TetPly(const std::function<void(size_t, uint8_t&, int32_t*, int32_t&, float&)>& face) {
  const RawMesh t = testing::PreciseTetrahedron();
  Bytes b;
  b.s = kPlyTetHeader;
  for (float x : t.positions) b << x;
  for (size_t f = 0; f < 4; ++f) {
    uint8_t n = 3;
    int32_t c[3] = {int32_t(t.triangles[3 * f]), int32_t(t.triangles[3 * f + 1]),
                    int32_t(t.triangles[3 * f + 2])};
    int32_t group = int32_t(f + 1);
    float load = float(f);
    face(f, n, c, group, load);
    b << n;
    for (uint8_t i = 0; i < n; ++i) b << (i < 3 ? c[i] : 0);
    b << group << load;
  }
  return b.s;
}

TEST_F(FastPathTest, PipeIsReadToItsEnd) {
  const std::string path = Path("pipe.off");
  ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
  const std::string text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  std::thread writer([&] { std::ofstream(path) << text; });
  absl::StatusOr<RawMesh> m = ReadMeshFile(path);
  writer.join();
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
  EXPECT_EQ(m->triangles, (std::vector<uint32_t>{0, 1, 2}));
}

TEST_F(FastPathTest, BinaryPlyRecordsReadInPlace) {
  absl::StatusOr<RawMesh> m =
      ReadMeshFile(Write("tet.ply", TetPly([](size_t, uint8_t&, int32_t*, int32_t&, float&) {})));
  ASSERT_TRUE(m.ok()) << m.status();
  const RawMesh t = testing::PreciseTetrahedron();
  EXPECT_EQ(m->positions, t.positions);
  EXPECT_EQ(m->triangles, t.triangles);
  EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{1, 2, 3, 4}));
  ASSERT_EQ(m->face_fields.size(), 1u);
  EXPECT_EQ(m->face_fields[0].values, (std::vector<float>{0, 1, 2, 3}));
}

// A record the fast loop does not take, in the middle of an element, is refused by the general
// loop with the face and its byte.
TEST_F(FastPathTest, BinaryPlyRecordItDoesNotTakeIsRefusedInTheGeneralWords) {
  const auto spoil = [&](const std::string& name, auto how) {
    return ReadError(
        Write(name, TetPly([&](size_t f, uint8_t& n, int32_t* c, int32_t& g, float& load) {
                if (f == 2) how(n, c, g, load);
              })));
  };
  // Vertices take 48 bytes, a face 21 (count, 3 corners, group, load): face 2 starts at byte 90;
  // the general loop names the byte after the value it refuses.
  const auto at = [](size_t byte) { return absl::StrCat("face 2 (byte ", byte, " of the body)"); };
  EXPECT_NE(spoil("edge.ply", [](uint8_t& n, int32_t*, int32_t&, float&) { n = 2; })
                .find(at(91) + " has 2 vertices"),
            std::string::npos);
  EXPECT_NE(spoil("neg.ply", [](uint8_t&, int32_t* c, int32_t&, float&) { c[1] = -1; })
                .find(at(99) + " has a negative vertex index -1"),
            std::string::npos);
  EXPECT_NE(spoil("group.ply", [](uint8_t&, int32_t*, int32_t& g, float&) { g = -5; })
                .find(at(107) + ": group -5 is not an integer in [0, 2^32)"),
            std::string::npos);
  EXPECT_NE(spoil("load.ply", [](uint8_t&, int32_t*, int32_t&,
                                 float& load) { load = std::numeric_limits<float>::quiet_NaN(); })
                .find(at(111) + ": field 'load' = nan is not a finite float"),
            std::string::npos);
  EXPECT_NE(spoil("range.ply", [](uint8_t&, int32_t* c, int32_t&, float&) { c[0] = 4; })
                .find("face 2 references vertex 4 but the file has 4 vertices"),
            std::string::npos);
}

// Other types and extra properties: the records are still of one size; a list besides the
// corners makes them differ, and the general loop reads the element.
TEST_F(FastPathTest, BinaryPlyOfOtherTypesAndExtraLists) {
  const RawMesh t = testing::PreciseTetrahedron();
  for (bool extra_list : {false, true}) {
    Bytes b;
    b.s = absl::StrCat(
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\n"
        "property uchar red\nproperty float y\nproperty double z\nelement face 4\n",
        extra_list ? "property list uchar float texcoord\n" : "",
        "property list uint uint vertex_indices\nproperty ushort group\nproperty double p\n"
        "end_header\n");
    for (size_t v = 0; v < 4; ++v)
      b << double(t.positions[3 * v]) << uint8_t{7} << t.positions[3 * v + 1]
        << double(t.positions[3 * v + 2]);
    for (size_t f = 0; f < 4; ++f) {
      if (extra_list) {  // f texture coordinates: records of four sizes
        b << uint8_t(f);
        for (size_t i = 0; i < f; ++i) b << 0.5f;
      }
      b << uint32_t{3} << t.triangles[3 * f] << t.triangles[3 * f + 1] << t.triangles[3 * f + 2]
        << uint16_t(10 + f) << double(f) / 4;
    }
    absl::StatusOr<RawMesh> m = ReadMeshFile(Write("types.ply", b.s));
    ASSERT_TRUE(m.ok()) << m.status();
    EXPECT_EQ(m->positions, t.positions);
    EXPECT_EQ(m->triangles, t.triangles);
    EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{10, 11, 12, 13}));
    ASSERT_EQ(m->face_fields.size(), 1u);
    EXPECT_EQ(m->face_fields[0].values, (std::vector<float>{0, 0.25f, 0.5f, 0.75f}));
  }
}

TEST_F(FastPathTest, HugeDeclaredCountsAreTruncationsNotAllocations) {
  std::string ply = kPlyTetHeader;
  ply.replace(ply.find("vertex 4"), 8, "vertex 4000000000");
  ply += std::string(48, '\0');  // four vertices
  EXPECT_NE(ReadError(Write("huge.ply", ply))
                .find("truncated: header announces 4000000000 vertices and 4 faces but the data "
                      "ends in vertex 4 (byte 48 of the body)"),
            std::string::npos);
  Bytes stl;
  stl.s.assign(80, ' ');
  stl << uint32_t{0xFFFFFFFF};
  stl.s += std::string(100, '\0');
  EXPECT_NE(ReadError(Write("huge.stl", stl.s))
                .find("header announces 4294967295 triangles (214748364834 bytes) but the file "
                      "has 184 bytes"),
            std::string::npos);
  const std::string off = "OFF\n4000000000 4000000000 0\n0 0 0\n";
  EXPECT_NE(ReadError(Write("huge.off", off)).find("the file ends after 1 vertices"),
            std::string::npos);
}

// Facets that share no corner: three vertices each, far more than the index's first guess.
TEST_F(FastPathTest, StlIndexGrowsPastItsFirstGuess) {
  RawMesh soup;
  for (uint32_t f = 0; f < 5000; ++f) {
    for (int k = 0; k < 3; ++k) {
      soup.positions.insert(soup.positions.end(), {float(f), float(k), float(f % 7)});
      soup.triangles.push_back(3 * f + k);
    }
  }
  for (bool binary : {true, false}) {
    const std::string path = Path(binary ? "apart.stl" : "apart_ascii.stl");
    ASSERT_TRUE((binary ? WriteMeshFile(path, soup) : WriteMeshFileAscii(path, soup)).ok());
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    ASSERT_TRUE(m.ok()) << m.status();
    EXPECT_EQ(m->positions, soup.positions);
    EXPECT_EQ(m->triangles, soup.triangles);
  }
}

// A corner seen again long after the recent-corner table forgot it is still the same vertex.
TEST_F(FastPathTest, StlCornersFarApartAreWelded) {
  RawMesh soup;
  soup.positions = {0, 0, 0};
  for (uint32_t f = 0; f < 20000; ++f) {
    soup.positions.insert(soup.positions.end(), {float(f + 1), 1, 0, float(f + 1), 2, 0});
    soup.triangles.insert(soup.triangles.end(), {0, 2 * f + 1, 2 * f + 2});
  }
  soup.triangles.insert(soup.triangles.end(), {1, 2, 0});  // the first facet's corners again
  const std::string path = Path("fan.stl");
  ASSERT_TRUE(WriteMeshFile(path, soup).ok());
  absl::StatusOr<RawMesh> m = ReadMeshFile(path);
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->positions, soup.positions);
  EXPECT_EQ(m->triangles, soup.triangles);
}

TEST_F(FastPathTest, TextNumbersAtTheEndsOfTheFloatRange) {
  const auto off = [&](const std::string& x) {
    return Write("n.off", "OFF\n3 1 0\n" + x + " 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  };
  for (const auto& [text, value] : std::vector<std::pair<std::string, float>>{
           {"1e-320", 0.0f},   // below the smallest denormal: zero
           {"1e-40", 1e-40f},  // a denormal
           {"-0", -0.0f},      // keeps its sign
           {"+1.5", 1.5f},     // a leading '+'
           {"3.4028235e38", 3.4028235e38f}}) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(off(text));
    ASSERT_TRUE(m.ok()) << text << ": " << m.status();
    EXPECT_EQ(std::bit_cast<uint32_t>(m->positions[0]), std::bit_cast<uint32_t>(value)) << text;
  }
  for (const std::string text : {"1e39", "inf", "-inf", "nan", "NaN"})
    EXPECT_NE(ReadError(off(text)).find("vertex 0 (line 3): coordinate '" + text +
                                        "' is not a finite float"),
              std::string::npos)
        << text;
  EXPECT_NE(ReadError(off("0x1p3")).find("cannot parse '0x1p3' as a number"), std::string::npos);
}

}  // namespace
}  // namespace femsimp
