// Face groups and face fields through the files that hold them (OBJ groups; PLY groups and
// fields, ASCII and binary; STL's named solids), the OBJ naming rules, foreign PLY and STL files,
// malformed attributes, and formats that cannot hold them.
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/io/face_data.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "gtest/gtest.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::TempDirTest;

constexpr auto kInvalid = absl::StatusCode::kInvalidArgument;

// The tetrahedron with four groups (one of them the default 0) and two fields whose values need
// every bit of a float.
RawMesh TetrahedronWithData() {
  RawMesh m = testing::PreciseTetrahedron();
  m.face_groups = {0, 7, 7, 4000000000u};
  m.face_fields = {{"pressure", {1.0f / 3.0f, -2.5e-7f, 101325.0f, 0.0f}},
                   {"shear", {3.14159265f, -1e30f, 1e-30f, 42.0f}}};
  return m;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void ExpectSameFaceData(const RawMesh& out, const RawMesh& in, bool fields) {
  EXPECT_EQ(out.positions, in.positions);
  EXPECT_EQ(out.triangles, in.triangles);
  EXPECT_EQ(out.face_groups, in.face_groups);
  if (!fields) {
    EXPECT_TRUE(out.face_fields.empty());
    return;
  }
  ASSERT_EQ(out.face_fields.size(), in.face_fields.size());
  for (size_t i = 0; i < in.face_fields.size(); ++i) {
    EXPECT_EQ(out.face_fields[i].name, in.face_fields[i].name);
    EXPECT_EQ(out.face_fields[i].values, in.face_fields[i].values) << in.face_fields[i].name;
  }
}

// ------------------------------------------------------------------------- round trips

class FaceDataRoundTrip : public testing::FileFormatTest {
 protected:
  bool HoldsFields() const { return GetParam().ext == ".ply"; }
};

TEST_P(FaceDataRoundTrip, Tetrahedron) {
  RawMesh in = TetrahedronWithData();
  if (!HoldsFields()) in.face_fields.clear();
  ASSERT_TRUE(Mesh::Build(in).ok());
  ExpectSameFaceData(RoundTrip(in), in, HoldsFields());
}

TEST_P(FaceDataRoundTrip, FandiskWithGroupsAndThreeFields) {
  absl::StatusOr<RawMesh> read = ReadMeshFile(testing::TestDataPath("fandisk.off"));
  ASSERT_TRUE(read.ok()) << read.status();
  RawMesh in = std::move(*read);
  const size_t nf = in.num_faces();
  in.face_groups.resize(nf);
  for (size_t f = 0; f < nf; ++f) in.face_groups[f] = uint32_t(f / 1000);  // runs of 1000
  if (HoldsFields()) {
    in.face_fields = {{"p", {}}, {"tau_x", {}}, {"temperature", {}}};
    for (size_t f = 0; f < nf; ++f) {
      in.face_fields[0].values.push_back(float(std::sin(double(f))));
      in.face_fields[1].values.push_back(float(f) * 1e-3f);
      in.face_fields[2].values.push_back(-273.15f + float(f % 97));
    }
  }
  ASSERT_TRUE(Mesh::Build(in).ok());
  ExpectSameFaceData(RoundTrip(in), in, HoldsFields());
}

TEST_P(FaceDataRoundTrip, NoDataStaysWithout) {
  const RawMesh out = RoundTrip(testing::PreciseTetrahedron());
  EXPECT_TRUE(out.face_groups.empty());
  EXPECT_TRUE(out.face_fields.empty());
}

INSTANTIATE_TEST_SUITE_P(Formats, FaceDataRoundTrip,
                         ::testing::Values(testing::FileFormat{".obj", true},
                                           testing::FileFormat{".ply", true},
                                           testing::FileFormat{".ply", false}),
                         testing::FileFormatName);

// ------------------------------------------------------------------------- STL solids

// Each facet as its group's name and its corners, as a multiset: an STL keeps neither the face
// order nor the vertex numbers.
std::multiset<std::pair<std::string, std::array<float, 9>>> NamedFacets(const RawMesh& m,
                                                                        const GroupNames& names) {
  std::multiset<std::pair<std::string, std::array<float, 9>>> facets;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    std::array<float, 9> corners;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) corners[3 * k + i] = m.positions[3 * m.triangles[3 * f + k] + i];
    facets.emplace(ObjGroupName(m.face_groups.empty() ? 0 : m.face_groups[f], names), corners);
  }
  return facets;
}

class StlSolidsTest : public TempDirTest {
 protected:
  // An ASCII STL of the tetrahedron's faces, `solids[f]` the `solid` line before face f when
  // it differs from the one before (CRLF line ends, keywords in either case, as tools write).
  std::string Stl(const std::string& name, const std::vector<std::string>& solids) {
    const RawMesh t = testing::PreciseTetrahedron();
    std::ostringstream s;
    s.precision(9);
    for (size_t f = 0; f < t.num_faces(); ++f) {
      if (f == 0 || solids[f] != solids[f - 1]) {
        if (f) s << "endsolid\r\n";
        s << solids[f] << "\r\n";
      }
      s << (f % 2 ? "FACET NORMAL 0 0 0\r\n  OUTER LOOP\r\n"
                  : "facet normal 0 0 0\r\nouter loop\r\n");
      for (int k = 0; k < 3; ++k) {
        const float* p = &t.positions[3 * t.triangles[3 * f + k]];
        s << "\t" << (f % 2 ? "VERTEX " : "vertex ") << p[0] << " " << p[1] << " " << p[2]
          << "\r\n";
      }
      s << "endloop\r\nendfacet\r\n";
    }
    return Write(name, s.str() + "endsolid\r\n");
  }
};

TEST_F(StlSolidsTest, SolidsOfOtherToolsAreNamedGroups) {
  GroupNames names;
  absl::StatusOr<RawMesh> m = ReadMeshFile(
      Stl("patches.stl", {"solid inlet", "SOLID", "solid  outer wall ", "solid inlet"}), &names);
  ASSERT_TRUE(m.ok()) << m.status();
  // Order of first appearance; an unnamed solid is "default" (0); the name is the rest of the
  // line, blanks at its ends stripped.
  EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{1, 0, 2, 1}));
  EXPECT_EQ(names, (GroupNames{{1, "inlet"}, {2, "outer wall"}}));
  EXPECT_EQ(m->num_vertices(), 4u);  // welded across the solids
}

TEST_F(StlSolidsTest, OneSolidNameIsNoGrouping) {
  for (const auto& solids :
       {std::vector<std::string>(4, "solid part"),
        std::vector<std::string>{"solid a", "solid a", "solid  a", "solid a"}}) {
    GroupNames names;
    absl::StatusOr<RawMesh> m = ReadMeshFile(Stl("one.stl", solids), &names);
    ASSERT_TRUE(m.ok()) << m.status();
    EXPECT_TRUE(m->face_groups.empty());
    EXPECT_TRUE(names.empty());
  }
}

TEST_F(StlSolidsTest, GroupsAreWrittenAsSolidsAndReadBack) {
  RawMesh tet = TetrahedronWithData();
  tet.face_fields.clear();
  absl::StatusOr<RawMesh> fandisk = ReadMeshFile(testing::TestDataPath("fandisk.off"));
  ASSERT_TRUE(fandisk.ok()) << fandisk.status();
  fandisk->face_groups.resize(fandisk->num_faces());
  for (size_t f = 0; f < fandisk->num_faces(); ++f)  // interleaved: written as one run per solid
    fandisk->face_groups[f] = uint32_t(f % 3 == 0 ? 5 : f / 4000);
  for (const RawMesh* in : {&tet, &*fandisk}) {
    const GroupNames names = {{7, "inlet"}, {5, "fixed support"}};
    const std::string path = Path("groups.stl");
    ASSERT_TRUE(WriteMeshFile(path, *in, names).ok());  // binary asked, ASCII written
    const std::string text = ReadText(path);
    ASSERT_EQ(text.rfind("solid ", 0), 0u) << text.substr(0, 80);
    GroupNames back_names;
    absl::StatusOr<RawMesh> back = ReadMeshFile(path, &back_names);
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(NamedFacets(*back, back_names), NamedFacets(*in, names));
    std::set<uint32_t> groups(in->face_groups.begin(), in->face_groups.end());
    size_t solids = 0;
    for (size_t at = text.find("solid "); at != std::string::npos;
         at = text.find("\nsolid ", at + 1))
      ++solids;
    EXPECT_EQ(solids, groups.size());
  }
  EXPECT_EQ(ReadText(Path("groups.stl")).find("solid fixed support\n"), 0u);  // face 0's
}

TEST_F(StlSolidsTest, WithoutGroupsStaysBinaryAndNamesThatDoNotReadBackAreRefused) {
  const std::string plain = Path("plain.stl");
  ASSERT_TRUE(WriteMeshFile(plain, testing::PreciseTetrahedron()).ok());
  EXPECT_EQ(ReadText(plain).size(), 84u + 50u * 4u);
  RawMesh m = testing::PreciseTetrahedron();
  m.face_groups = {1, 1, 2, 2};
  for (const std::string name : {" inlet", "inlet\t", "two\nlines", ""}) {
    absl::Status s = WriteMeshFile(Path("bad.stl"), m, GroupNames{{2, name}});
    EXPECT_EQ(s.code(), kInvalid) << s;
    EXPECT_NE(s.message().find("cannot be an STL solid name"), std::string::npos) << s;
  }
}

// ------------------------------------------------------------------------- OBJ names

class ObjGroupsTest : public TempDirTest {
 protected:
  // The tetrahedron's vertices, then `body` (faces and group statements).
  std::string Obj(const std::string& name, const std::string& body) {
    std::ostringstream s;
    const RawMesh t = testing::PreciseTetrahedron();
    for (size_t v = 0; v < t.num_vertices(); ++v)
      s << "v " << t.positions[3 * v] << " " << t.positions[3 * v + 1] << " "
        << t.positions[3 * v + 2] << "\n";
    return Write(name, s.str() + body);
  }
};

TEST_F(ObjGroupsTest, NamesMapToIdsAndBack) {
  const std::string path = Obj("named.obj",
                               "f 1 3 2\n"  // before any g: default, id 0
                               "g wall\nf 1 2 4\n"
                               "g group_1\nf 2 3 4\n"
                               "g inlet  outlet\nf 1 4 3\n");
  GroupNames names;
  absl::StatusOr<RawMesh> m = ReadMeshFile(path, &names);
  ASSERT_TRUE(m.ok()) << m.status();
  // group_1 takes id 1, so "wall" (first other name) gets 2 and "inlet outlet" 3.
  EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{0, 2, 1, 3}));
  EXPECT_EQ(names, (GroupNames{{2, "wall"}, {3, "inlet outlet"}}));

  const std::string again = Path("again.obj");
  ASSERT_TRUE(WriteMeshFile(again, *m, names).ok());
  const std::string text = ReadText(again);
  for (const char* line : {"g default\n", "g wall\n", "g group_1\n", "g inlet outlet\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << " not in:\n" << text;
  GroupNames names2;
  absl::StatusOr<RawMesh> m2 = ReadMeshFile(again, &names2);
  ASSERT_TRUE(m2.ok()) << m2.status();
  EXPECT_EQ(m2->face_groups, m->face_groups);
  EXPECT_EQ(names2, names);
}

TEST_F(ObjGroupsTest, WithoutNamesIdsAreWrittenAsGroupN) {
  RawMesh in = testing::PreciseTetrahedron();
  in.face_groups = {5, 5, 0, 12};
  const std::string path = Path("ids.obj");
  ASSERT_TRUE(WriteMeshFile(path, in).ok());
  const std::string text = ReadText(path);
  EXPECT_NE(text.find("g group_5\nf 1 3 2\nf 1 2 4\ng default\nf 2 3 4\ng group_12\nf 1 4 3\n"),
            std::string::npos)
      << text;
  GroupNames names;
  absl::StatusOr<RawMesh> out = ReadMeshFile(path, &names);
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->face_groups, in.face_groups);
  EXPECT_TRUE(names.empty());
}

TEST_F(ObjGroupsTest, OnlyDefaultGroupMeansNoGroups) {
  absl::StatusOr<RawMesh> m =
      ReadMeshFile(Obj("default.obj", "g default\nf 1 3 2\nf 1 2 4\ng\nf 2 3 4\nf 1 4 3\n"));
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_TRUE(m->face_groups.empty());
  // Non-canonical numbers are plain names, not ids.
  GroupNames names;
  m = ReadMeshFile(Obj("odd.obj", "g group_01\nf 1 3 2\nf 1 2 4\ng 7\nf 2 3 4\nf 1 4 3\n"), &names);
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{1, 1, 2, 2}));
  EXPECT_EQ(names, (GroupNames{{1, "group_01"}, {2, "7"}}));
}

TEST(ObjGroupIds, SkipsIdsTakenByCanonicalNames) {
  GroupNames names;
  EXPECT_EQ(ObjGroupIds({"a", "group_1", "group_3", "b", "default", "c"}, &names),
            (std::vector<uint32_t>{2, 1, 3, 4, 0, 5}));
  EXPECT_EQ(names, (GroupNames{{2, "a"}, {4, "b"}, {5, "c"}}));
  EXPECT_EQ(ObjGroupName(4, names), "b");
  EXPECT_EQ(ObjGroupName(9, names), "group_9");
  EXPECT_EQ(ObjGroupName(0, names), "default");
}

// ------------------------------------------------------------------------- foreign PLY

class PlyFaceDataTest : public TempDirTest {
 protected:
  // An ASCII PLY of the tetrahedron whose faces have `props` (header lines without "property")
  // and, after each face's indices, the tokens in `values[face]`.
  std::string Ply(const std::string& name, const std::vector<std::string>& props,
                  const std::vector<std::string>& values) {
    const RawMesh t = testing::PreciseTetrahedron();
    std::ostringstream s;
    s << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nelement face 4\nproperty list uchar int vertex_indices\n";
    for (const std::string& p : props) s << "property " << p << "\n";
    s << "end_header\n";
    for (size_t v = 0; v < 4; ++v)
      s << t.positions[3 * v] << " " << t.positions[3 * v + 1] << " " << t.positions[3 * v + 2]
        << "\n";
    for (size_t f = 0; f < 4; ++f)
      s << "3 " << t.triangles[3 * f] << " " << t.triangles[3 * f + 1] << " "
        << t.triangles[3 * f + 2] << " " << values[f] << "\n";
    return Write(name, s.str());
  }
  void ExpectReadError(const std::string& path, const std::string& part) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    ASSERT_FALSE(m.ok()) << path << " was accepted";
    EXPECT_EQ(m.status().code(), kInvalid) << m.status();
    EXPECT_NE(m.status().message().find(part), std::string::npos)
        << "'" << part << "' not in: " << m.status();
  }
};

TEST_F(PlyFaceDataTest, OtherToolsPropertiesAreSortedOut) {
  // Normals, colours and integer flags are no fields; a double is read as a float field.
  const std::string path = Ply("foreign.ply",
                               {"float nx", "float ny", "float nz", "uchar red", "uchar green",
                                "uchar blue", "int flags", "short group", "double pressure"},
                               {"0 0 1 255 0 0 9 3 1.5", "0 0 1 255 0 0 9 3 -2",
                                "0 0 1 255 0 0 9 0 0.25", "0 0 1 255 0 0 9 12 1e5"});
  absl::StatusOr<RawMesh> m = ReadMeshFile(path);
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{3, 3, 0, 12}));
  ASSERT_EQ(m->face_fields.size(), 1u);
  EXPECT_EQ(m->face_fields[0].name, "pressure");
  EXPECT_EQ(m->face_fields[0].values, (std::vector<float>{1.5f, -2.0f, 0.25f, 1e5f}));
  EXPECT_TRUE(Mesh::Build(*m).ok());
}

TEST_F(PlyFaceDataTest, AllZeroGroupsMeanNoGroups) {
  absl::StatusOr<RawMesh> m = ReadMeshFile(Ply("zero.ply", {"uint group"}, {"0", "0", "0", "0"}));
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_TRUE(m->face_groups.empty());
}

TEST_F(PlyFaceDataTest, BigEndianBinary) {
  const RawMesh t = testing::PreciseTetrahedron();
  std::string s =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
      "property int group\nproperty float load\nend_header\n";
  const auto put = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    if constexpr (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(v));
    s.append(b, sizeof(v));
  };
  for (float x : t.positions) put(x);
  for (size_t f = 0; f < 4; ++f) {
    put(uint8_t{3});
    for (int i = 0; i < 3; ++i) put(int32_t(t.triangles[3 * f + i]));
    put(int32_t(f + 1));
    put(float(f) * 0.5f);
  }
  absl::StatusOr<RawMesh> m = ReadMeshFile(Write("be.ply", s));
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_EQ(m->positions, t.positions);
  EXPECT_EQ(m->face_groups, (std::vector<uint32_t>{1, 2, 3, 4}));
  ASSERT_EQ(m->face_fields.size(), 1u);
  EXPECT_EQ(m->face_fields[0].values, (std::vector<float>{0.f, 0.5f, 1.f, 1.5f}));
}

TEST_F(PlyFaceDataTest, MalformedAttributes) {
  const std::vector<std::string> four = {"1 2 3 4", "1 2 3 4", "1 2 3 4", "1 2 3 4"};
  ExpectReadError(Ply("four.ply", {"float a", "float b", "float c", "float d"}, four),
                  "4 float face properties (a, b, c, d) but femsimp carries at most 3 face fields");
  const std::vector<std::string> one = {"1", "2", "3", "4"};
  ExpectReadError(Ply("float_group.ply", {"float group"}, one),
                  "face property 'group' must be a scalar of an integer type");
  ExpectReadError(Ply("list_group.ply", {"list uchar int group"}, {"1 1", "1 1", "1 1", "1 1"}),
                  "face property 'group' must be a scalar of an integer type");
  ExpectReadError(Ply("twice.ply", {"float p", "float p"}, {"1 1", "1 1", "1 1", "1 1"}),
                  "face property 'p' is declared twice");
  ExpectReadError(Ply("negative.ply", {"int group"}, {"1", "-1", "3", "4"}),
                  "face 1 (line 16): group -1 is not an integer in [0, 2^32)");
  ExpectReadError(Ply("fraction.ply", {"int group"}, {"1", "2", "2.5", "4"}),
                  "group 2.5 is not an integer");
  ExpectReadError(Ply("huge.ply", {"uint group"}, {"1", "2", "3", "4294967296"}),
                  "group 4.29497e+09 is not an integer in [0, 2^32)");
  ExpectReadError(Ply("inf.ply", {"float p"}, {"1", "inf", "3", "4"}),
                  "face 1 (line 16): field 'p' = inf is not a finite float");
  ExpectReadError(Ply("overflow.ply", {"double p"}, {"1", "2", "1e300", "4"}),
                  "field 'p' = 1e+300 is not a finite float");
  ExpectReadError(Ply("junk.ply", {"float p"}, {"1", "2", "high", "4"}),
                  "cannot parse 'high' as a number");
}

TEST_F(PlyFaceDataTest, TruncatedBinaryWithFields) {
  const std::string path = Path("data.ply");
  ASSERT_TRUE(WriteMeshFile(path, TetrahedronWithData()).ok());
  const std::string data = ReadText(path);
  for (size_t cut : {size_t{1}, size_t{4}, size_t{9}}) {
    const std::string cut_path = Write("cut.ply", data.substr(0, data.size() - cut));
    ExpectReadError(cut_path, "the data ends in face 3");
  }
}

// ------------------------------------------------------------------------- writing

class WriteFaceDataTest : public TempDirTest {
 protected:
  void ExpectWriteError(const std::string& name, const RawMesh& mesh, const std::string& part) {
    absl::Status s = WriteMeshFile(Path(name), mesh);
    ASSERT_FALSE(s.ok()) << name << " was written";
    EXPECT_EQ(s.code(), kInvalid) << s;
    EXPECT_NE(s.message().find(part), std::string::npos) << "'" << part << "' not in: " << s;
    EXPECT_NE(s.message().find(Path(name)), std::string::npos) << "path missing: " << s;
  }
};

TEST_F(WriteFaceDataTest, FormatsThatCannotHoldThemRefuse) {
  const RawMesh both = TetrahedronWithData();
  RawMesh groups_only = both;
  groups_only.face_fields.clear();
  ExpectWriteError("m.off", both,
                   "OFF files cannot hold face groups and face fields (pressure, shear); write "
                   ".ply to keep them");
  ExpectWriteError("m.stl", both, "STL files cannot hold face fields (pressure, shear)");
  EXPECT_TRUE(WriteMeshFile(Path("m.stl"), groups_only).ok());  // as named solids
  ExpectWriteError("m.obj", both, "OBJ files cannot hold face fields (pressure, shear)");
  EXPECT_TRUE(WriteMeshFile(Path("m.obj"), groups_only).ok());

  // All faces in group 0 is no grouping: nothing is lost.
  RawMesh zero = testing::PreciseTetrahedron();
  zero.face_groups.assign(4, 0);
  EXPECT_TRUE(WriteMeshFile(Path("zero.stl"), zero).ok());

  // Dropped on request, the rest is written.
  for (const char* name : {"d.off", "d.stl", "d.obj", "d.ply"}) {
    RawMesh m = both;
    DropUnheldFaceData(MeshFileExtension(name), &m);
    ASSERT_TRUE(WriteMeshFile(Path(name), m).ok()) << name;
    absl::StatusOr<RawMesh> back = ReadMeshFile(Path(name));
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(back->face_groups.empty(), std::string(name) == "d.off") << name;
    EXPECT_EQ(back->face_fields.size(), std::string(name) == "d.ply" ? 2u : 0u) << name;
  }
}

TEST_F(WriteFaceDataTest, BadFieldsAreRefused) {
  RawMesh m = TetrahedronWithData();
  m.face_fields[1].name = "wall shear";
  ExpectWriteError("blank.ply", m, "face field 'wall shear': not usable as a PLY property name");
  m.face_fields[1].name = "nx";
  ExpectWriteError("nx.ply", m, "face field 'nx': not usable");
  m.face_fields[1].name = "group";
  ExpectWriteError("group.ply", m, "face field 'group': not usable");
  m.face_fields[1].name = "pressure";
  ExpectWriteError("twice.ply", m, "face field 'pressure' is given twice");
  m = TetrahedronWithData();
  m.face_fields[0].values[2] = std::nanf("");
  ExpectWriteError("nan.ply", m, "face field 'pressure': face 2 has a non-finite value");
  m = TetrahedronWithData();
  m.face_fields[0].values.pop_back();
  ExpectWriteError("short.ply", m, "face field 'pressure' has 3 values for 4 faces");
  m = TetrahedronWithData();
  m.face_fields.push_back({"a", {1, 2, 3, 4}});
  m.face_fields.push_back({"b", {1, 2, 3, 4}});
  ExpectWriteError("many.ply", m, "face fields: 4 given, at most 3");
}

TEST_F(WriteFaceDataTest, MultiLineGroupNameIsRefused) {
  RawMesh m = testing::PreciseTetrahedron();
  m.face_groups = {1, 1, 2, 2};
  absl::Status s = WriteMeshFile(Path("m.obj"), m, GroupNames{{2, "two\nlines"}});
  EXPECT_EQ(s.code(), kInvalid) << s;
  EXPECT_NE(s.message().find("group 2: name 'two\nlines' cannot be an OBJ group name"),
            std::string::npos)
      << s;
}

}  // namespace
}  // namespace femsimp
