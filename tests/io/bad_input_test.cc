// Every class of bad input: what makes the file unreadable (syntax, truncation, indices beyond
// the file's vertices, non-finite numbers) fails in ReadMeshFile, in every format alike;
// geometric and topological defects (degenerate, duplicate, flipped, non-manifold faces) pass
// through it unchanged, in every format alike, and fail in Mesh::Build (the repair stage,
// tests/engine/repair_test.cc, fixes them). Each case checks the code and the message.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "gtest/gtest.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

class BadInputTest : public testing::TempDirTest {
 protected:
  void ExpectReadError(const std::string& path, absl::StatusCode code, const std::string& part) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    ASSERT_FALSE(m.ok()) << path << " was accepted";
    EXPECT_EQ(m.status().code(), code) << m.status();
    EXPECT_NE(m.status().message().find(part), std::string::npos)
        << "'" << part << "' not in: " << m.status();
    EXPECT_NE(m.status().message().find(path), std::string::npos) << "path missing: " << m.status();
  }
  void ExpectBuildError(const std::string& path, const std::string& part) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    ASSERT_TRUE(m.ok()) << m.status();
    absl::StatusOr<Mesh> mesh = Mesh::Build(*m);
    ASSERT_FALSE(mesh.ok()) << path << " was accepted by Mesh::Build";
    EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(mesh.status().message().find(part), std::string::npos)
        << "'" << part << "' not in: " << mesh.status();
  }
  // An OFF file from its vertex lines and face lines.
  std::string Off(const std::string& name, const std::vector<std::string>& vertices,
                  const std::vector<std::string>& faces) {
    std::ostringstream s;
    s << "OFF\n" << vertices.size() << " " << faces.size() << " 0\n";
    for (const auto& v : vertices) s << v << "\n";
    for (const auto& f : faces) s << f << "\n";
    return Write(name, s.str());
  }
  std::string Truncate(const std::string& path, size_t bytes) {
    std::ifstream in(path, std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return Write("cut_" + path.substr(path.rfind('/') + 1), data.substr(0, data.size() - bytes));
  }
};

constexpr auto kInvalid = absl::StatusCode::kInvalidArgument;
const std::vector<std::string> kSquare = {"0 0 0", "1 0 0", "1 1 0", "0 1 0"};

// ------------------------------------------------------------------------- file level

TEST_F(BadInputTest, MissingFile) {
  ExpectReadError(Path("absent.off"), absl::StatusCode::kNotFound, "no such file");
}

TEST_F(BadInputTest, Directory) {
  std::filesystem::create_directory(Path("dir.off"));
  ExpectReadError(Path("dir.off"), absl::StatusCode::kFailedPrecondition, "is a directory");
}

TEST_F(BadInputTest, UnreadableFile) {
  if (geteuid() == 0) GTEST_SKIP() << "root reads any file";
  const std::string path = Off("locked.off", kSquare, {"3 0 1 2"});
  chmod(path.c_str(), 0);
  ExpectReadError(path, absl::StatusCode::kPermissionDenied, "cannot open for reading");
}

TEST_F(BadInputTest, UnknownExtension) {
  ExpectReadError(
      Write("mesh.xyz", "OFF\n"), kInvalid,
      "unsupported mesh file extension '.xyz' (supported: .off, .obj, .stl, .ply, .msh)");
  ExpectReadError(Write("mesh", "OFF\n"), kInvalid, "unsupported mesh file extension ''");
}

TEST_F(BadInputTest, EmptyFile) {
  for (const char* name : {"empty.off", "empty.obj", "empty.stl", "empty.ply"})
    ExpectReadError(Write(name, ""), kInvalid, "file is empty");
}

TEST_F(BadInputTest, TruncatedOffFaces) {
  ExpectReadError(Write("t.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"),
                  kInvalid,
                  "truncated: header announces 4 vertices and 3 faces but the file ends after "
                  "2 faces");
}

TEST_F(BadInputTest, TruncatedOffVertices) {
  ExpectReadError(Write("t.off", "OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n"), kInvalid,
                  "ends after 3 vertices");
}

TEST_F(BadInputTest, TruncatedBinaryStl) {
  const std::string path = Path("tet.stl");
  ASSERT_TRUE(WriteMeshFile(path, testing::PreciseTetrahedron()).ok());
  ExpectReadError(Truncate(path, 30), kInvalid,
                  "binary STL size mismatch (truncated?): header announces 4 triangles (284 "
                  "bytes) but the file has 254 bytes");
}

// What CAD exporters write as binary STL: a header that begins with "solid", a facet count of 0
// (a writer that streams and never seeks back) or padding after the facets. Each reads the
// facets the file holds, and says what it did.
TEST_F(BadInputTest, BinaryStlWithAWrongCountReadsItsFacetsAndSaysSo) {
  const std::string path = Path("tet.stl");
  ASSERT_TRUE(WriteMeshFile(path, testing::PreciseTetrahedron()).ok());
  std::ifstream in(path, std::ios::binary);
  const std::string tet((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(tet.size(), 84u + 4 * 50);
  absl::StatusOr<RawMesh> plain = ReadMeshFile(path);
  ASSERT_TRUE(plain.ok()) << plain.status();
  const std::string header = std::string("solid part1 exported").append(60, ' ');
  const std::string facets = tet.substr(84);
  const auto read = [&](const std::string& name, const std::string& count,
                        const std::string& tail) {
    std::vector<std::string> warnings;
    absl::StatusOr<RawMesh> m =
        ReadMeshFile(Write(name, header + count + facets + tail), nullptr, &warnings);
    EXPECT_TRUE(m.ok()) << name << ": " << m.status();
    if (m.ok()) {
      EXPECT_EQ(m->triangles, plain->triangles) << name;
      EXPECT_EQ(m->positions, plain->positions) << name;
    }
    return absl::StrJoin(warnings, "; ");
  };
  const std::string four("\x04\0\0\0", 4), none(4, '\0');
  EXPECT_EQ(read("solid_header.stl", four, ""), "");
  EXPECT_EQ(read("count0.stl", none, ""),
            "binary STL: the header announces 0 facets but the file holds 4; read them all");
  EXPECT_EQ(read("count0_padded.stl", none, std::string(7, '\0')),
            "binary STL: the header announces 0 facets but the file holds 4; read them all and "
            "left out the 7 bytes after them");
  EXPECT_EQ(read("padded.stl", four, std::string(57, '\0')),
            "binary STL: left out the 57 bytes after the 4 facets the header announces");
  // More facets announced than the bytes hold is a cut file, "solid" or not.
  ExpectReadError(Write("five.stl", header + std::string("\x05\0\0\0", 4) + facets + "xx"),
                  kInvalid,
                  "header announces 5 triangles (334 bytes) but the file has 286 bytes (4 whole "
                  "facets)");
}

// A binary file read as text is quoted escaped and cut short, not dumped into the message.
TEST_F(BadInputTest, BinaryBytesInATextFileAreQuotedEscaped) {
  std::string junk = "solid x\n";
  junk += "\x01\x02\xff";
  junk += std::string(100, 'z');
  ExpectReadError(Write("junk.stl", junk + "\n"), kInvalid,
                  "line 2: unexpected '\\x01\\x02\\xffzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzz...' in "
                  "ASCII STL");
  ExpectReadError(Write("junk.obj", junk.substr(8) + "\n"), kInvalid,
                  "line 1: unknown OBJ statement '\\x01\\x02\\xffzzz");
}

TEST_F(BadInputTest, TruncatedAsciiStl) {
  const std::string path = Path("tet.stl");
  ASSERT_TRUE(WriteMeshFileAscii(path, testing::PreciseTetrahedron()).ok());
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Cut before the last facet's third corner.
  ExpectReadError(Write("cut.stl", text.substr(0, text.rfind("vertex"))), kInvalid,
                  "truncated: the file ends inside facet 3");
  // Without 'endsolid' (some writers leave it out; a cut between facets looks the same): every
  // whole facet is read, and the warning says both.
  const size_t last = text.rfind("endfacet");
  ASSERT_NE(last, std::string::npos);
  const std::string cut = text.substr(0, text.find('\n', last) + 1);
  const size_t lines = std::count(cut.begin(), cut.end(), '\n');
  std::vector<std::string> warnings;
  absl::StatusOr<RawMesh> m = ReadMeshFile(Write("no_end.stl", cut), nullptr, &warnings);
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->num_faces(), 4u);
  EXPECT_EQ(absl::StrJoin(warnings, "; "),
            absl::StrCat("ASCII STL: no 'endsolid' (the file ends at line ", lines,
                         " after 4 whole facets): read them all; was the file cut short?"));
}

TEST_F(BadInputTest, TruncatedPly) {
  const std::string binary = Path("tet.ply");
  ASSERT_TRUE(WriteMeshFile(binary, testing::PreciseTetrahedron()).ok());
  ExpectReadError(Truncate(binary, 5), kInvalid,
                  "truncated: header announces 4 vertices and 4 faces but the data ends in "
                  "face 3");
  const std::string ascii = Path("tet_ascii.ply");
  ASSERT_TRUE(WriteMeshFileAscii(ascii, testing::PreciseTetrahedron()).ok());
  ExpectReadError(Truncate(ascii, 4), kInvalid, "the data ends in face 3");
}

// An element without properties holds no data, however many the header announces: it is
// skipped at once (the fuzzer found a header announcing 3e17 of them, which hung the reader).
TEST_F(BadInputTest, PlyElementWithoutPropertiesHoldsNoData) {
  for (const std::string format : {"ascii", "binary_little_endian"}) {
    std::string data = "ply\nformat " + format +
                       " 1.0\nelement marker 333333333333956782\nelement vertex 3\n"
                       "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                       "property list uchar int vertex_indices\nend_header\n";
    if (format == "ascii") {
      data += "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    } else {
      const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
      data.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
      const uint8_t n = 3;
      const int32_t corners[3] = {0, 1, 2};
      data.append(reinterpret_cast<const char*>(&n), 1);
      data.append(reinterpret_cast<const char*>(corners), sizeof corners);
    }
    absl::StatusOr<RawMesh> m = ReadMeshFile(Write("marker_" + format + ".ply", data));
    ASSERT_TRUE(m.ok()) << format << ": " << m.status();
    EXPECT_EQ(m->num_vertices(), 3u) << format;
    EXPECT_EQ(m->num_faces(), 1u) << format;
  }
}

// "OFF BINARY" as OpenMesh writes it: little-endian counts, float points, int faces.
std::string BinaryOff(const RawMesh& m) {
  std::string s = "OFF BINARY\n";
  const auto put = [&](const auto& v) { s.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
  put(int32_t(m.num_vertices()));
  put(int32_t(m.num_faces()));
  put(int32_t(0));
  for (float x : m.positions) put(x);
  for (size_t f = 0; f < m.num_faces(); ++f) {
    put(int32_t(3));
    for (int i = 0; i < 3; ++i) put(int32_t(m.triangles[3 * f + i]));
  }
  return s;
}

TEST_F(BadInputTest, BinaryOffReadsAndTruncationIsCaught) {
  const std::string data = BinaryOff(testing::PreciseTetrahedron());
  absl::StatusOr<RawMesh> m = ReadMeshFile(Write("bin.off", data));
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->positions, testing::PreciseTetrahedron().positions);
  EXPECT_EQ(m->triangles, testing::PreciseTetrahedron().triangles);
  ExpectReadError(Write("cut.off", data.substr(0, data.size() - 8)), kInvalid,
                  "binary OFF truncated: header announces 4 vertices and 4 faces");
}

TEST_F(BadInputTest, GarbageText) {
  const std::string junk = "hello world\nthis is not a mesh\n";
  ExpectReadError(Write("g.off", junk), kInvalid, "expected an OFF header, found 'hello'");
  ExpectReadError(Write("g.obj", junk), kInvalid, "line 1: unknown OBJ statement 'hello'");
  ExpectReadError(Write("g.stl", junk), kInvalid, "not an ASCII STL");
  ExpectReadError(Write("g.ply", junk), kInvalid, "not a PLY file");
}

TEST_F(BadInputTest, UnparsableNumber) {
  ExpectReadError(Off("n.off", {"0 0 0", "1 zero 0", "1 1 0"}, {"3 0 1 2"}), kInvalid,
                  "vertex 1 (line 4): cannot parse 'zero' as a number");
  ExpectReadError(Write("n.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0 \nf 1 2 x\n"), kInvalid,
                  "face 0 (line 4): invalid vertex index 'x'");
}

// Polygons of 4 to 64 corners are cut into triangles (tests/io/polygons_test.cc); a face of fewer
// corners, or of more, is refused by face and line.
TEST_F(BadInputTest, FaceOfTooFewOrTooManyCorners) {
  ExpectReadError(Off("two.off", kSquare, {"3 0 1 2", "2 0 1"}), kInvalid,
                  "face 1 (line 8) has 2 vertices: a face needs 3");
  // OpenMesh's OBJ reader would drop a two-corner face silently.
  ExpectReadError(Write("two.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\n"), kInvalid,
                  "face 0 (line 4) has 2 vertices: a face needs 3");
  std::string ring = "f";
  for (int i = 1; i <= 65; ++i) absl::StrAppend(&ring, " ", 1 + i % 4);
  ExpectReadError(Write("ring.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + ring + "\n"), kInvalid,
                  "face 0 (line 5) has 65 vertices: femsimp cuts polygons of up to 64 corners "
                  "into triangles; triangulate this one first");
  ExpectReadError(Write("q.ply",
                        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 0\n"),
                  kInvalid, "has 1 vertices: a face needs 3");
}

TEST_F(BadInputTest, NonFiniteCoordinate) {
  ExpectReadError(Off("nan.off", {"0 0 0", "nan 0 0", "1 1 0"}, {"3 0 1 2"}), kInvalid,
                  "vertex 1 (line 4): coordinate 'nan' is not a finite float");
  ExpectReadError(Off("inf.off", {"0 0 0", "1 0 0", "1 -inf 0"}, {"3 0 1 2"}), kInvalid,
                  "vertex 2 (line 5): coordinate '-inf' is not a finite float");
  ExpectReadError(Off("big.off", {"0 0 0", "1 0 0", "1 1e39 0"}, {"3 0 1 2"}), kInvalid,
                  "coordinate '1e39' is not a finite float");
  ExpectReadError(Write("nan.obj", "v 0 0 0\nv 1 NaN 0\nv 1 1 0\nf 1 2 3\n"), kInvalid,
                  "vertex 1 (line 2): coordinate 'NaN' is not a finite float");
  // Binary files carry the NaN bits: the writer does not refuse them, the reader does.
  RawMesh tet = testing::PreciseTetrahedron();
  tet.positions[4] = std::numeric_limits<float>::quiet_NaN();
  ASSERT_TRUE(WriteMeshFile(Path("nan.ply"), tet).ok());
  ExpectReadError(Path("nan.ply"), kInvalid, "vertex 1 (byte");
  ExpectReadError(Path("nan.ply"), kInvalid, "coordinate y = nan is not a finite float");
  ASSERT_TRUE(WriteMeshFile(Path("nan.stl"), tet).ok());
  ExpectReadError(Path("nan.stl"), kInvalid, "has a non-finite coordinate nan");
}

TEST_F(BadInputTest, NegativeIndex) {
  ExpectReadError(Off("neg.off", kSquare, {"3 0 1 -1"}), kInvalid,
                  "face 0 (line 7) has a negative vertex index -1");
  ExpectReadError(Write("neg.obj", "v 0 0 0\nv 1 0 0\nf 1 2 -3\n"), kInvalid,
                  "relative index '-3' points before the first vertex");
}

TEST_F(BadInputTest, IndexOutOfRange) {
  ExpectReadError(Off("r.off", kSquare, {"3 0 1 2", "3 0 2 7"}), kInvalid,
                  "face 1 (line 8) references vertex 7 but the file has 4 vertices");
  ExpectReadError(Write("r.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n"), kInvalid,
                  "face 0 (line 4) references vertex 8 but the file has 3 vertices");
  ExpectReadError(Write("r.ply",
                        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n1 1 0\n3 0 1 5\n"),
                  kInvalid, "face 0 references vertex 5 but the file has 3 vertices");
  RawMesh tet = testing::PreciseTetrahedron();
  tet.triangles[5] = 9;
  ExpectReadError(Write("r_bin.off", BinaryOff(tet)), kInvalid,
                  "face 1 (byte 76 after the header) references vertex 9 but the file has 4 "
                  "vertices");
  // OBJ faces may name vertices defined after them.
  absl::StatusOr<RawMesh> forward =
      ReadMeshFile(Write("fwd.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"));
  ASSERT_TRUE(forward.ok()) << forward.status();
  EXPECT_EQ(forward->num_faces(), 1u);
}

TEST_F(BadInputTest, NonFiniteBinaryOffCoordinate) {
  RawMesh tet = testing::PreciseTetrahedron();
  tet.positions[4] = std::numeric_limits<float>::quiet_NaN();
  ExpectReadError(Write("nan_bin.off", BinaryOff(tet)), kInvalid,
                  "vertex 1 (byte 24 after the header): coordinate 1 = nan is not a finite float");
}

// ------------------------------------------------------------------------- topology

// Degenerate faces are a defect of the mesh, not of the file: every reader passes them on (an
// STL facet with two equal corners too, after its corners became vertices), and validation
// refuses them with their face number.
TEST_F(BadInputTest, DegenerateFace) {
  ExpectBuildError(Off("d.off", kSquare, {"3 0 1 2", "3 0 2 2"}),
                   "face 1 is degenerate: vertices (0, 2, 2) repeat an index");
  ExpectBuildError(Write("d.ply",
                         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                         "property float y\nproperty float z\nelement face 1\n"
                         "property list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 0\n1 1 0\n3 0 1 0\n"),
                   "face 0 is degenerate");
  ExpectBuildError(Write("d.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 3 -1\n"),
                   "face 1 is degenerate: vertices (0, 2, 2) repeat an index");
  ExpectBuildError(Write("d.stl",
                         "solid d\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                         "vertex 0 0 0\nendloop\nendfacet\nendsolid d\n"),
                   "face 0 is degenerate: vertices (0, 1, 0) repeat an index");
}

TEST_F(BadInputTest, ZeroAreaFace) {
  ExpectBuildError(Off("z.off", {"0 0 0", "1 0 0", "2 0 0"}, {"3 0 1 2"}),
                   "face 0 (0, 1, 2) has zero area");
}

TEST_F(BadInputTest, DuplicateFaces) {
  ExpectBuildError(Off("dup.off", kSquare, {"3 0 1 2", "3 0 1 2"}),
                   "faces 0 and 1 both use edge (2, 0) in the same direction: inconsistent "
                   "orientation or duplicate face");
  ExpectBuildError(Off("pillow.off", kSquare, {"3 0 1 2", "3 0 2 1"}),
                   "faces 0 and 1 are duplicates (same three vertices)");
}

TEST_F(BadInputTest, NonManifoldEdge) {
  // Three triangles hinge on edge (0, 1).
  ExpectBuildError(Off("nme.off", {"0 0 0", "1 0 0", "0 1 0", "0 -1 0", "0 0 1"},
                       {"3 0 1 2", "3 1 0 3", "3 0 1 4"}),
                   "non-manifold edge (0, 1): shared by 3 faces");
}

TEST_F(BadInputTest, NonManifoldVertex) {
  // Two triangles touching only at vertex 0.
  ExpectBuildError(
      Off("bowtie.off", {"0 0 0", "1 0 0", "0 1 0", "-1 0 0", "0 -1 0"}, {"3 0 1 2", "3 0 3 4"}),
      "vertex 0 is non-manifold: 2 boundary fans meet there");
  // Two closed tetrahedra sharing vertex 0: no boundary, two fans.
  ExpectBuildError(
      Off("tets.off", {"0 0 0", "1 0 0", "0 1 0", "0 0 1", "-1 0 0", "0 -1 0", "0 0 -1"},
          {"3 0 2 1", "3 0 1 3", "3 1 2 3", "3 0 3 2", "3 0 5 4", "3 0 4 6", "3 4 5 6", "3 0 6 5"}),
      "vertex 0 is non-manifold: its 6 faces form more than one fan");
}

TEST_F(BadInputTest, InconsistentOrientation) {
  ExpectBuildError(Off("o.off", kSquare, {"3 0 1 2", "3 0 3 2"}), "faces 0 and 1 both use edge");
}

TEST_F(BadInputTest, NoFaces) {
  ExpectBuildError(Off("none.off", {"0 0 0", "1 0 0", "1 1 0"}, {}),
                   "mesh is empty (3 vertices, 0 faces)");
  ExpectBuildError(Write("none.obj", "# only a comment\nv 0 0 0\n"),
                   "mesh is empty (1 vertices, 0 faces)");
}

}  // namespace
}  // namespace femsimp
