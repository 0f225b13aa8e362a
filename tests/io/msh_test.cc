// gmsh MSH files (engine/io/msh.h): the same small model by hand in 4.1 and 2.2, ASCII and binary
// (binary generated here, in both byte orders), a model gmsh itself meshed, femsimp's 4.1 output
// read back by femsimp, gmsh and meshio, and every refusal with its line or byte.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "absl/strings/str_split.h"
#include "engine/io/mesh_io.h"
#include "engine/io/mesh_readers.h"
#include "engine/mesh.h"
#include "gtest/gtest.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

// The model of every hand-made file: the corner tetrahedron, outward, its nodes tagged 10 (origin),
// 20 (x), 30 (y), 40 (z) and listed 40, 10, 30, 20, then node 50 that no triangle uses; its bottom
// in physical group 5 "inlet", the other three faces in group 9 "wall with spaces"; besides the
// triangles a point element and two line elements (physical 3 "edge", dimension 1).
constexpr char kAscii41[] = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Comments
sections femsimp does not know are skipped
$EndComments
$PhysicalNames
3
1 3 "edge"
2 5 "inlet"
2 9 "wall with spaces"
$EndPhysicalNames
$Entities
1 1 2 0
1 0 0 0 0
1 0 0 0 1 0 0 1 3 2 1 -1
1 0 0 0 1 1 0 1 5 0
2 0 0 0 1 1 1 1 9 0
$EndEntities
$Nodes
2 5 10 50
2 1 0 3
40
10
30
0 0 1
0 0 0
0 1 0
2 2 1 2
20
50
1 0 0 0.5 0.5
9 9 9 0.25 0.75
$EndNodes
$Elements
4 7 1 8
0 1 15 1
8 10
1 1 1 2
6 10 20
7 20 30
2 1 2 1
1 10 30 20
2 2 2 3
2 10 20 40
3 20 30 40
4 10 40 30
$EndElements
)";

constexpr char kAscii22[] = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 5 "inlet"
2 9 "wall with spaces"
$EndPhysicalNames
$Nodes
5
40 0 0 1
10 0 0 0
30 0 1 0
20 1 0 0
50 9 9 9
$EndNodes
$Elements
7
8 15 2 0 1 10
6 1 2 3 1 10 20
7 1 2 3 1 20 30
1 2 2 5 1 10 30 20
2 2 2 9 2 10 20 40
3 2 2 9 2 20 30 40
4 2 3 9 2 0 10 40 30
$EndElements
)";

RawMesh ExpectedModel() {
  RawMesh m;
  m.positions = {0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0};
  m.triangles = {1, 2, 3, 1, 3, 0, 3, 2, 0, 1, 0, 2};
  m.face_groups = {5, 9, 9, 9};
  return m;
}
const GroupNames kModelNames = {{5, "inlet"}, {9, "wall with spaces"}};
const std::vector<std::string> kModelWarnings = {
    "msh: left out 2 lines, 1 point, 1 node no triangle uses"};

// Binary MSH data in either byte order; offset() marks where the next value goes.
class Binary {
 public:
  // size_bytes: the file's size_t (MSH 4.1's data-size).
  explicit Binary(bool swap, int size_bytes = 8) : swap_(swap), size_bytes_(size_bytes) {}
  Binary& Text(const std::string& t) {
    s_ += t;
    return *this;
  }
  template <typename T>
  Binary& Put(T v) {
    auto b = std::bit_cast<std::array<char, sizeof(T)>>(v);
    if (swap_) std::reverse(b.begin(), b.end());
    s_.append(b.data(), b.size());
    return *this;
  }
  Binary& Int(int32_t v) { return Put(v); }
  Binary& Size(uint64_t v) { return size_bytes_ == 4 ? Put(uint32_t(v)) : Put(v); }
  Binary& Xyz(double x, double y, double z) { return Put(x).Put(y).Put(z); }
  template <typename... T>
  Binary& Ints(T... v) {
    (Int(int32_t(v)), ...);
    return *this;
  }
  template <typename... T>
  Binary& Sizes(T... v) {
    (Size(uint64_t(v)), ...);
    return *this;
  }
  size_t offset() const { return s_.size(); }
  const std::string& bytes() const { return s_; }

 private:
  bool swap_;
  int size_bytes_;
  std::string s_;
};

// The hand-made model as binary 4.1 with size_t of `size_bytes`; node 40's x is `x40`, x40_at
// (if given) receives its offset.
std::string Binary41(bool swap, double x40 = 0, size_t* x40_at = nullptr, int size_bytes = 8) {
  Binary b(swap, size_bytes);
  b.Text(absl::StrCat("$MeshFormat\n4.1 1 ", size_bytes, "\n")).Int(1).Text("\n$EndMeshFormat\n");
  b.Text("$PhysicalNames\n3\n1 3 \"edge\"\n2 5 \"inlet\"\n2 9 \"wall with spaces\"\n");
  b.Text("$EndPhysicalNames\n$Entities\n").Sizes(1, 1, 2, 0);
  b.Int(1).Xyz(0, 0, 0).Size(0);
  b.Int(1).Xyz(0, 0, 0).Xyz(1, 0, 0).Size(1).Int(3).Size(2).Ints(1, -1);
  b.Int(1).Xyz(0, 0, 0).Xyz(1, 1, 0).Size(1).Int(5).Size(0);
  b.Int(2).Xyz(0, 0, 0).Xyz(1, 1, 1).Size(1).Int(9).Size(0);
  b.Text("\n$EndEntities\n$Nodes\n").Sizes(2, 5, 10, 50);
  b.Ints(2, 1, 0).Size(3).Sizes(40, 10, 30);
  if (x40_at) *x40_at = b.offset();
  b.Xyz(x40, 0, 1).Xyz(0, 0, 0).Xyz(0, 1, 0);
  b.Ints(2, 2, 1).Size(2).Sizes(20, 50).Xyz(1, 0, 0).Put(0.5).Put(0.5).Xyz(9, 9, 9);
  b.Put(0.25).Put(0.75);
  b.Text("\n$EndNodes\n$Elements\n").Sizes(4, 7, 1, 8);
  b.Ints(0, 1, 15).Size(1).Sizes(8, 10);
  b.Ints(1, 1, 1).Size(2).Sizes(6, 10, 20).Sizes(7, 20, 30);
  b.Ints(2, 1, 2).Size(1).Sizes(1, 10, 30, 20);
  b.Ints(2, 2, 2).Size(3).Sizes(2, 10, 20, 40).Sizes(3, 20, 30, 40).Sizes(4, 10, 40, 30);
  b.Text("\n$EndElements\n");
  return b.bytes();
}

std::string Binary22(bool swap) {
  Binary b(swap);
  b.Text("$MeshFormat\n2.2 1 8\n").Int(1).Text("\n$EndMeshFormat\n");
  b.Text("$PhysicalNames\n2\n2 5 \"inlet\"\n2 9 \"wall with spaces\"\n$EndPhysicalNames\n");
  b.Text("$Nodes\n5\n");
  b.Int(40).Xyz(0, 0, 1).Int(10).Xyz(0, 0, 0).Int(30).Xyz(0, 1, 0).Int(20).Xyz(1, 0, 0);
  b.Int(50).Xyz(9, 9, 9);
  b.Text("\n$EndNodes\n$Elements\n7\n");
  b.Ints(15, 1, 2).Ints(8, 0, 1, 10);
  b.Ints(1, 2, 2).Ints(6, 1, 2, 10, 20).Ints(7, 1, 2, 20, 30);
  b.Ints(2, 3, 2).Ints(1, 5, 1, 10, 30, 20).Ints(2, 9, 2, 10, 20, 40).Ints(3, 9, 2, 20, 30, 40);
  b.Ints(2, 1, 3).Ints(4, 9, 2, 0, 10, 40, 30);
  b.Text("\n$EndElements\n");
  return b.bytes();
}

// 1-based line of the first `needle` in `text`.
size_t LineOf(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + std::count(text.begin(), text.begin() + std::min(at, text.size()), '\n');
}

// Runs /usr/bin/python3 on `script` (written to the directory) and returns what it printed.
std::string RunPython(const std::string& dir, const std::string& script) {
  const std::string path = dir + "/script.py";
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return "cannot write " + path;
  std::fputs(script.c_str(), f);
  std::fclose(f);
  const std::string command = absl::StrCat("cd '", dir, "' && /usr/bin/python3 script.py 2>&1");
  FILE* p = popen(command.c_str(), "r");
  if (!p) return "cannot run python3";
  std::string out;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof(buf), p)) out.append(buf, n);
  const int rc = pclose(p);
  return rc == 0 ? out : absl::StrCat("python3 failed (", rc, "): ", out);
}

class MshTest : public testing::TempDirTest {
 protected:
  struct Read {
    RawMesh mesh;
    GroupNames names;
    std::vector<std::string> warnings;
  };
  Read ReadOk(const std::string& path) {
    Read r;
    absl::StatusOr<RawMesh> m = ReadMeshFile(path, &r.names, &r.warnings);
    EXPECT_TRUE(m.ok()) << m.status();
    if (m.ok()) r.mesh = *std::move(m);
    return r;
  }
  void ExpectModel(const std::string& name, const std::string& bytes) {
    SCOPED_TRACE(name);
    const Read r = ReadOk(Write(name, bytes));
    const RawMesh want = ExpectedModel();
    EXPECT_EQ(r.mesh.positions, want.positions);
    EXPECT_EQ(r.mesh.triangles, want.triangles);
    EXPECT_EQ(r.mesh.face_groups, want.face_groups);
    EXPECT_EQ(r.names, kModelNames);
    EXPECT_EQ(r.warnings, kModelWarnings);
    EXPECT_TRUE(Mesh::Build(r.mesh).ok());
  }
  void ExpectError(const std::string& name, const std::string& bytes, const std::string& part) {
    absl::StatusOr<ParsedMeshFile> m = ParseMeshFile(".msh", bytes);
    ASSERT_FALSE(m.ok()) << name << " was accepted";
    EXPECT_EQ(m.status().code(), absl::StatusCode::kInvalidArgument) << m.status();
    EXPECT_NE(m.status().message().find(part), std::string::npos)
        << name << ": '" << part << "' not in: " << m.status();
  }
};

TEST_F(MshTest, HandMadeFilesOfEveryVersionAndEncoding) {
  ExpectModel("ascii41.msh", kAscii41);
  ExpectModel("ascii22.msh", kAscii22);
  for (bool swap : {false, true}) {
    ExpectModel(swap ? "binary41_swapped.msh" : "binary41.msh", Binary41(swap));
    ExpectModel(swap ? "binary22_swapped.msh" : "binary22.msh", Binary22(swap));
  }
  // A 4.1 file written where size_t has 4 bytes.
  ExpectModel("binary41_size4.msh", Binary41(false, 0, nullptr, 4));
  // Windows line ends read the same.
  ExpectModel("crlf41.msh", absl::StrReplaceAll(kAscii41, {{"\n", "\r\n"}}));
}

TEST_F(MshTest, ElementsOfOtherTypesAreCountedByKind) {
  // Two tetrahedra (one of second order) on the model's nodes: left out, counted.
  std::string text =
      absl::StrReplaceAll(kAscii22, {{"$Elements\n7\n", "$Elements\n10\n"},
                                     {"$EndElements",
                                      "11 4 2 1 1 10 20 30 40\n12 4 0 10 20 30 40\n"
                                      "13 11 0 10 20 30 40 10 20 30 40 10 20\n$EndElements"}});
  const Read r = ReadOk(Write("tets.msh", text));
  EXPECT_EQ(r.mesh.num_faces(), 4u);
  EXPECT_EQ(r.warnings,
            std::vector<std::string>{"msh: left out 2 lines, 2 tetrahedra, "
                                     "1 10-node tetrahedron, 1 point, 1 node no triangle uses"});
  // Post-processing data is said to be left out too.
  text = absl::StrCat(kAscii41,
                      "$ElementData\n1\n\"pressure\"\n1\n0\n3\n0\n1\n1\n1 2.5\n$EndElementData\n");
  EXPECT_EQ(ReadOk(Write("data.msh", text)).warnings,
            (std::vector<std::string>{kModelWarnings[0],
                                      "msh: left out 1 $ElementData (femsimp reads no fields from "
                                      "MSH files)"}));
}

TEST_F(MshTest, WithoutPhysicalGroupsThereAreNoGroups) {
  const std::string text = absl::StrReplaceAll(
      kAscii41,
      {{"1 0 0 0 1 1 0 1 5 0\n2 0 0 0 1 1 1 1 9 0", "1 0 0 0 1 1 0 0 0\n2 0 0 0 1 1 1 0 0"}});
  const Read r = ReadOk(Write("plain.msh", text));
  EXPECT_EQ(r.mesh.num_faces(), 4u);
  EXPECT_TRUE(r.mesh.face_groups.empty());
}

TEST_F(MshTest, FileMadeByGmsh) {
  // A box meshed into tetrahedra, its six sides in two named physical groups and the volume in a
  // third, saved by gmsh in every version and encoding femsimp reads, and partitioned.
  const std::string out = RunPython(dir_, R"(
import gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
box = gmsh.model.occ.addBox(0, 0, 0, 1, 0.6, 0.4)
gmsh.model.occ.synchronize()
sides = [t for d, t in gmsh.model.getEntities(2)]
gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, sides[:1], 7), "inlet")
gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, sides[1:], 12), "wall")
gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [box], 1), "solid")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.15)
gmsh.model.mesh.generate(3)
for version in ["4.1", "2.2"]:
    for binary in [0, 1]:
        gmsh.option.setNumber("Mesh.MshFileVersion", float(version))
        gmsh.option.setNumber("Mesh.Binary", binary)
        gmsh.write("box_%s_%d.msh" % (version, binary))
print(len(gmsh.model.mesh.getElementsByType(2)[0]), len(gmsh.model.mesh.getElementsByType(4)[0]),
      len(gmsh.model.mesh.getElementsByType(2, sides[0])[0]))
# Partitioned: the elements move to partition entities ($PartitionedEntities).
gmsh.model.mesh.partition(3)
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write("box_partitioned.msh")
gmsh.finalize()
)");
  std::vector<std::string> counts = absl::StrSplit(out, absl::ByAnyChar(" \n"), absl::SkipEmpty());
  ASSERT_EQ(counts.size(), 3u) << out;
  const size_t triangles = std::stoul(counts[0]), tets = std::stoul(counts[1]);
  const size_t inlet = std::stoul(counts[2]);
  ASSERT_GT(tets, 0u);
  Read first;
  for (const char* name : {"box_4.1_0.msh", "box_4.1_1.msh", "box_2.2_0.msh", "box_2.2_1.msh",
                           "box_partitioned.msh"}) {
    SCOPED_TRACE(name);
    const Read r = ReadOk(Path(name));
    EXPECT_EQ(r.mesh.num_faces(), triangles);
    EXPECT_EQ(std::count(r.mesh.face_groups.begin(), r.mesh.face_groups.end(), 7u), inlet);
    EXPECT_EQ(std::count(r.mesh.face_groups.begin(), r.mesh.face_groups.end(), 12u),
              triangles - inlet);
    EXPECT_EQ(r.names, (GroupNames{{7, "inlet"}, {12, "wall"}}));
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_TRUE(
        absl::StartsWith(r.warnings[0], absl::StrCat("msh: left out ", tets, " tetrahedra, ")))
        << r.warnings[0];
    absl::StatusOr<Mesh> mesh = Mesh::Build(r.mesh);
    EXPECT_TRUE(mesh.ok()) << mesh.status();  // closed and consistently oriented
    if (first.mesh.num_faces() == 0) {
      first = r;
    } else if (!absl::StrContains(name, "partitioned")) {  // every version and encoding: one soup
      EXPECT_EQ(r.mesh.positions, first.mesh.positions);
      EXPECT_EQ(r.mesh.triangles, first.mesh.triangles);
      EXPECT_EQ(r.mesh.face_groups, first.mesh.face_groups);
    }
  }
}

TEST_F(MshTest, WrittenFileReadsBackWithGroupsAndNames) {
  // Faces in groups 0 (none), 3 (no name) and 7 (named), interleaved.
  RawMesh mesh = testing::MakeTorus(12, 8);
  mesh.face_groups.resize(mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f) mesh.face_groups[f] = f < 40 ? 0 : f < 100 ? 3 : 7;
  const GroupNames names = {{7, "outlet side"}, {99, "no faces"}};
  const std::string path = Path("out.msh");
  ASSERT_TRUE(WriteMeshFile(path, mesh, names).ok());
  const Read r = ReadOk(path);
  EXPECT_EQ(r.mesh.positions, mesh.positions);
  EXPECT_EQ(r.mesh.triangles, mesh.triangles);  // groups are contiguous here: the order stays
  EXPECT_EQ(r.mesh.face_groups, mesh.face_groups);
  EXPECT_EQ(r.names, (GroupNames{{7, "outlet side"}}));  // names of groups without faces go
  EXPECT_TRUE(r.warnings.empty());
  const std::string text = testing::ReadFileBytes(path);
  EXPECT_TRUE(absl::StartsWith(text, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")) << text;
  EXPECT_NE(text.find("$PhysicalNames\n1\n2 7 \"outlet side\"\n$EndPhysicalNames\n"),
            std::string::npos);

  // gmsh and meshio read it: faces per physical group, and the name.
  const std::string out = RunPython(dir_, R"(
import collections, gmsh, meshio
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.open("out.msh")
for dim, tag in gmsh.model.getPhysicalGroups():
    n = sum(len(gmsh.model.mesh.getElementsByType(2, e)[0])
            for e in gmsh.model.getEntitiesForPhysicalGroup(dim, tag))
    print("gmsh", dim, tag, repr(gmsh.model.getPhysicalName(dim, tag)), n)
print("gmsh all", len(gmsh.model.mesh.getElementsByType(2)[0]))
gmsh.finalize()
m = meshio.read("out.msh")
count = collections.Counter()
for block, phys in zip(m.cells, m.cell_data.get("gmsh:physical", [])):
    count.update(int(p) for p in phys)
print("meshio", len(m.points), sum(len(b.data) for b in m.cells), sorted(count.items()),
      sorted((k, int(v[0])) for k, v in m.field_data.items()))
)");
  EXPECT_NE(out.find("gmsh 2 3 '' 60\n"), std::string::npos) << out;
  EXPECT_NE(out.find("gmsh 2 7 'outlet side' 92\n"), std::string::npos) << out;
  EXPECT_NE(out.find("gmsh all 192\n"), std::string::npos) << out;
  EXPECT_NE(out.find("meshio 96 192 [(0, 40), (3, 60), (7, 92)] [('outlet side', 7)]"),
            std::string::npos)
      << out;
}

TEST_F(MshTest, RoundTripKeepsEveryBit) {
  absl::StatusOr<RawMesh> in = ReadMeshFile(testing::TestDataPath("fandisk.off"));
  ASSERT_TRUE(in.ok()) << in.status();
  const std::string path = Path("fandisk.msh");
  ASSERT_TRUE(WriteMeshFile(path, *in).ok());
  const Read r = ReadOk(path);
  EXPECT_EQ(r.mesh.positions, in->positions);
  EXPECT_EQ(r.mesh.triangles, in->triangles);
  EXPECT_TRUE(r.mesh.face_groups.empty());
}

TEST_F(MshTest, FieldsAreRefusedAndNamesMustFitQuotes) {
  RawMesh mesh = testing::WithGroupsAndFields(testing::MakeTorus(12, 8));
  absl::Status s = WriteMeshFile(Path("f.msh"), mesh);
  EXPECT_NE(s.message().find("MSH files cannot hold face fields (pressure, heat_flux); write .ply"),
            std::string::npos)
      << s;
  mesh.face_fields.clear();
  EXPECT_TRUE(WriteMeshFile(Path("g.msh"), mesh).ok());
  s = WriteMeshFile(Path("q.msh"), mesh, {{mesh.face_groups[0], "say \"hi\""}});
  EXPECT_NE(s.message().find("cannot be an MSH physical name"), std::string::npos) << s;
}

TEST_F(MshTest, UnreadableFilesNameTheLineOrByte) {
  const std::string a41 = kAscii41, a22 = kAscii22;
  ExpectError("version", absl::StrReplaceAll(a41, {{"4.1 0 8", "3.0 0 8"}}),
              "unknown MSH version '3.0' (line 2): femsimp reads 2.2 and 4.1");
  ExpectError("version 4.0", absl::StrReplaceAll(a41, {{"4.1 0 8", "4 0 8"}}),
              "MSH version 4 is not supported (2.2 and 4.1 are)");
  ExpectError("not msh", "solid x\nendsolid x\n",
              "not a gmsh MSH file: expected '$MeshFormat' (line 1), found 'solid x'");

  // Truncated, in text and in binary.
  const std::string cut = a41.substr(0, a41.find("0 1 0\n2 2 1 2"));
  ExpectError("cut ascii", cut,
              absl::StrCat("truncated: the file ends inside $Nodes (line ",
                           LineOf(a41, "0 1 0\n2 2"), ")"));
  for (const std::string& bin : {Binary41(false), Binary22(true)}) {
    const std::string part = bin.substr(0, bin.find("$EndElements") - 9);
    ExpectError("cut binary", part,
                absl::StrCat("truncated: the file ends inside $Elements (byte ", part.size(), ")"));
  }
  ExpectError("cut section", a41.substr(0, a41.find("$EndElements")),
              "truncated: the file ends inside $Elements");
  ExpectError("unclosed", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Comments\nhello\n",
              "truncated: $Comments without '$EndComments'");

  // A section that does not end where its counts say.
  ExpectError("bad end", absl::StrReplaceAll(a41, {{"$EndNodes", "$EndNodez"}}),
              absl::StrCat("expected '$EndNodes' (line ", LineOf(a41, "$EndNodes"),
                           "), found '$EndNodez'"));
  ExpectError("extra value", absl::StrReplaceAll(a22, {{"50 9 9 9", "50 9 9 9 9"}}),
              absl::StrCat("expected '$EndNodes' (line ", LineOf(a22, "50 9 9 9"), "), found '9'"));
  ExpectError("no section", absl::StrReplaceAll(a41, {{"$Comments", "Comments"}}),
              "expected a section ('$Name') (line 4), found 'Comments'");
  ExpectError("bad number", absl::StrReplaceAll(a22, {{"30 0 1 0", "30 0 one 0"}}),
              absl::StrCat("node 30 (line ", LineOf(a22, "30 0 1 0"),
                           "): cannot parse 'one' as a coordinate"));

  // An element naming a node $Nodes does not define.
  ExpectError("missing node 4.1", absl::StrReplaceAll(a41, {{"4 10 40 30", "4 10 40 31"}}),
              absl::StrCat("element 4 (line ", LineOf(a41, "4 10 40 30"),
                           ") references node 31, which $Nodes does not define"));
  ExpectError("missing node 2.2", absl::StrReplaceAll(a22, {{"2 9 2 10 20 40", "2 9 2 10 21 40"}}),
              absl::StrCat("element 2 (line ", LineOf(a22, "2 9 2 10 20 40"),
                           ") references node 21, which $Nodes does not define"));
  ExpectError(
      "node twice", absl::StrReplaceAll(a22, {{"50 9 9 9", "40 9 9 9"}}),
      absl::StrCat("$Nodes (line ", LineOf(a22, "50 9 9 9"), "): node 40 is defined twice"));

  // Coordinates that are not finite floats.
  ExpectError("nan", absl::StrReplaceAll(a22, {{"50 9 9 9", "50 9 nan 9"}}),
              absl::StrCat("node 50 (line ", LineOf(a22, "50 9 9 9"),
                           "): coordinate 'nan' is not a finite float"));
  ExpectError("overflow", absl::StrReplaceAll(a41, {{"0 0 1\n0 0 0", "0 0 1e39\n0 0 0"}}),
              absl::StrCat("node 40 (line ", LineOf(a41, "0 0 1\n0 0 0"),
                           "): coordinate '1e39' is not a finite float"));
  size_t at = 0;
  const std::string nan = Binary41(false, std::numeric_limits<double>::quiet_NaN(), &at);
  ExpectError("binary nan", nan,
              absl::StrCat("node 40 (byte ", at, "): coordinate nan is not a finite float"));
  const std::string inf = Binary41(true, 1e300, &at);
  ExpectError("binary inf", inf,
              absl::StrCat("node 40 (byte ", at, "): coordinate 1e+300 is not a finite float"));

  // Binary byte order, element types, data size.
  std::string bad_one = Binary41(false);
  bad_one[20] = 7;  // the int 1 after "4.1 1 8\n"
  ExpectError("byte order", bad_one,
              "$MeshFormat (byte 20): binary file without the int 1 that gives its byte order");
  ExpectError("type", absl::StrReplaceAll(a41, {{"0 1 15 1", "0 1 200 1"}}),
              absl::StrCat("$Elements (line ", LineOf(a41, "0 1 15 1"),
                           "): element type 200 is not a gmsh element type"));
  ExpectError("data size", absl::StrReplaceAll(a22, {{"2.2 0 8", "2.2 0 4"}}),
              "$MeshFormat (line 2): data-size '4' is not 8");
  ExpectError("no triangles",
              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
              "4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n",
              "no 3-node triangles or 4-node quadrangles (element types 2 and 3) in the file, only "
              "1 tetrahedron");
}

}  // namespace
}  // namespace femsimp
