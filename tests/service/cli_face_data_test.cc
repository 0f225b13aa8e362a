// `femsimp simplify` (in process; local, and remote for MSH) with face groups and fields: they
// reach OUT, OBJ group names, STL solid names and MSH physical names survive, and an OUT format
// that cannot hold them stops the run before it starts unless --drop-face-data.

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "client/args.h"
#include "client/exit_codes.h"
#include "client/local_run.h"
#include "client/remote_run.h"
#include "engine/io/mesh_io.h"
#include "gtest/gtest.h"
#include "tests/service/test_util.h"
#include "tests/support/files.h"

namespace femsimp {
namespace {

namespace fs = std::filesystem;

class CliFaceDataTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    input_ = Path("in.ply");
    ASSERT_TRUE(
        WriteMeshFileAscii(input_, testing::WithGroupsAndFields(testing::MakeTorus(40, 24))).ok());
  }

  int Run(std::vector<std::string> args) {
    args.insert(args.begin(), {"femsimp", "simplify"});
    args.insert(args.end(), {"--preset", "paper", "--ratio", "0.5", "--quiet", "--threads", "2"});
    absl::StatusOr<cli::Command> cmd = cli::ParseCommandLine(args);
    EXPECT_TRUE(cmd.ok()) << cmd.status();
    if (!cmd.ok()) return -1;
    return cmd->simplify.server.empty() ? cli::RunLocal(cmd->simplify)
                                        : cli::RunRemote(cmd->simplify);
  }

  std::string input_;
};

TEST_F(CliFaceDataTest, GroupsAndFieldsReachThePly) {
  for (const char* name : {"out.ply", "OUT.PLY"}) {
    ASSERT_EQ(Run({input_, Path(name), "--stats-json", Path("stats.json")}), cli::kExitOk);
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path(name));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(out->num_faces(), 960u);
    EXPECT_EQ(testing::ExpectGroupsAndFields(*out), 4u);
    const std::string json = testing::ReadFileBytes(Path("stats.json"));
    EXPECT_NE(json.find("\"face_data\": {\"groups\": 4, \"fields\": [\"pressure\", \"heat_flux\"], "
                        "\"dropped\": null}"),
              std::string::npos)
        << json;
  }
}

TEST_F(CliFaceDataTest, ObjGroupNamesSurvive) {
  RawMesh mesh = testing::WithGroupsAndFields(testing::MakeTorus(40, 24));
  mesh.face_fields.clear();
  const GroupNames names = {{10, "inlet"}, {11, "wall"}, {13, "outlet"}};  // 12: group_12
  ASSERT_TRUE(WriteMeshFile(Path("in.obj"), mesh, names).ok());
  ASSERT_EQ(Run({Path("in.obj"), Path("out.obj")}), cli::kExitOk);
  const std::string text = testing::ReadFileBytes(Path("out.obj"));
  for (const char* line : {"\ng inlet\n", "\ng wall\n", "\ng group_12\n", "\ng outlet\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line;
  GroupNames read_names;
  absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.obj"), &read_names);
  ASSERT_TRUE(out.ok()) << out.status();
  // Ids are assigned anew on reading, but faces keep their groups: compare by name.
  ASSERT_EQ(out->face_groups.size(), out->num_faces());
  size_t per_name[4] = {0, 0, 0, 0};
  for (uint32_t g : out->face_groups) {
    const std::string name = ObjGroupName(g, read_names);
    for (int k = 0; k < 4; ++k)
      per_name[k] += name == std::vector<std::string>{"inlet", "wall", "group_12", "outlet"}[k];
  }
  EXPECT_EQ(per_name[0] + per_name[1] + per_name[2] + per_name[3], out->num_faces());
  for (size_t n : per_name) EXPECT_GT(n, 0u);
}

TEST_F(CliFaceDataTest, MshPhysicalGroupsKeepTheirNames) {
  RawMesh mesh = testing::WithGroupsAndFields(testing::MakeTorus(40, 24));
  mesh.face_fields.clear();
  const GroupNames names = {{10, "inlet"}, {11, "wall"}, {13, "outlet"}};  // 12: no name
  ASSERT_TRUE(WriteMeshFile(Path("in.msh"), mesh, names).ok());
  // A second $Elements section with a tetrahedron: left out, and said so.
  const std::string text = testing::ReadFileBytes(Path("in.msh")) +
                           "$Elements\n1 1 1 1\n3 1 4 1\n9999 1 2 3 4\n$EndElements\n";
  Write("in.msh", text);
  // Locally and through a server: the file I/O is the client's either way.
  testing::InProcessServer server;
  for (const std::string where : {"", "--server"}) {
    SCOPED_TRACE(where.empty() ? "local" : "remote");
    std::vector<std::string> args = {Path("in.msh"), Path("out.msh"), "--stats-json",
                                     Path("stats.json")};
    if (!where.empty()) args.insert(args.end(), {"--server", server.address()});
    ::testing::internal::CaptureStdout();
    const int code = Run(args);
    const std::string summary = ::testing::internal::GetCapturedStdout();
    ASSERT_EQ(code, cli::kExitOk);
    EXPECT_NE(summary.find("\nwarning:  msh: left out 1 tetrahedron\n"), std::string::npos)
        << summary;
    const std::string json = testing::ReadFileBytes(Path("stats.json"));
    EXPECT_NE(json.find("\"warnings\": [\"msh: left out 1 tetrahedron\"]"), std::string::npos)
        << json;
    const std::string out_text = testing::ReadFileBytes(Path("out.msh"));
    EXPECT_NE(out_text.find("$PhysicalNames\n3\n"), std::string::npos) << out_text.substr(0, 200);
    for (const char* line : {"\n2 10 \"inlet\"\n", "\n2 11 \"wall\"\n", "\n2 13 \"outlet\"\n"})
      EXPECT_NE(out_text.find(line), std::string::npos) << line;
    GroupNames read_names;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.msh"), &read_names);
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(read_names, names);
    EXPECT_EQ(out->num_faces(), 960u);
    for (uint32_t g : {10u, 11u, 12u, 13u})
      EXPECT_GT(std::count(out->face_groups.begin(), out->face_groups.end(), g), 0) << g;
  }
}

TEST_F(CliFaceDataTest, StlSolidNamesSurviveLocallyAndThroughTheServer) {
  RawMesh mesh = testing::WithGroupsAndFields(testing::MakeTorus(40, 24));
  mesh.face_fields.clear();
  const GroupNames names = {{10, "inlet"}, {11, "wall"}, {13, "outlet"}};  // 12: group_12
  ASSERT_TRUE(WriteMeshFile(Path("in.stl"), mesh, names).ok());
  testing::InProcessServer server;
  for (const std::string where : {"", "--server"}) {
    SCOPED_TRACE(where.empty() ? "local" : "remote");
    std::vector<std::string> args = {Path("in.stl"), Path("out.stl")};
    if (!where.empty()) args.insert(args.end(), {"--server", server.address()});
    ::testing::internal::CaptureStdout();
    const int code = Run(args);
    const std::string summary = ::testing::internal::GetCapturedStdout();
    ASSERT_EQ(code, cli::kExitOk);
    EXPECT_NE(summary.find("\nface data: 4 groups; the STL output is ASCII, one solid per group\n"),
              std::string::npos)
        << summary;
    const std::string text = absl::StrCat("\n", testing::ReadFileBytes(Path("out.stl")));
    for (const char* line : {"\nsolid inlet\n", "\nsolid wall\n", "\nsolid group_12\n",
                             "\nsolid outlet\n", "\nendsolid outlet\n"})
      EXPECT_NE(text.find(line), std::string::npos) << line;
    GroupNames read_names;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.stl"), &read_names);
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(out->num_faces(), 960u);
    std::set<std::string> seen;
    for (uint32_t g : out->face_groups) seen.insert(ObjGroupName(g, read_names));
    EXPECT_EQ(seen, (std::set<std::string>{"inlet", "wall", "group_12", "outlet"}));
  }
}

TEST_F(CliFaceDataTest, ObjNameThatMshCannotHoldStopsBeforeTheRun) {
  RawMesh mesh = testing::WithGroupsAndFields(testing::MakeTorus(40, 24));
  mesh.face_fields.clear();
  ASSERT_TRUE(WriteMeshFile(Path("in.obj"), mesh, {{10, "the \"inlet\""}}).ok());
  EXPECT_EQ(Run({Path("in.obj"), Path("out.msh")}), cli::kExitOutputFailed);
  EXPECT_FALSE(fs::exists(Path("out.msh")));
  EXPECT_EQ(Run({Path("in.obj"), Path("out.obj")}), cli::kExitOk);  // OBJ holds it
}

TEST_F(CliFaceDataTest, UnheldFaceDataStopsBeforeTheRun) {
  for (const char* name : {"out.stl", "out.off", "out.obj", "out.msh"}) {
    EXPECT_EQ(Run({input_, Path(name)}), cli::kExitOutputFailed) << name;
    EXPECT_FALSE(fs::exists(Path(name))) << name;
  }
}

TEST_F(CliFaceDataTest, DropFaceDataWritesWhatTheFormatHolds) {
  ASSERT_EQ(Run({input_, Path("out.off"), "--drop-face-data", "--stats-json", Path("s.json")}),
            cli::kExitOk);
  EXPECT_TRUE(ReadMeshFile(Path("out.off")).ok());
  EXPECT_NE(
      testing::ReadFileBytes(Path("s.json")).find("\"dropped\": \"face groups and face fields\""),
      std::string::npos);

  for (const char* name : {"out.obj", "out.stl"}) {  // both keep the groups
    ASSERT_EQ(Run({input_, Path(name), "--drop-face-data", "--stats-json", Path("s.json")}),
              cli::kExitOk);
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path(name));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(out->face_groups.size(), out->num_faces()) << name;
    EXPECT_TRUE(out->face_fields.empty());
    EXPECT_NE(testing::ReadFileBytes(Path("s.json")).find("\"dropped\": \"face fields\""),
              std::string::npos);
  }

  // Nothing to drop: the flag changes nothing.
  ASSERT_EQ(Run({input_, Path("out.ply"), "--drop-face-data"}), cli::kExitOk);
  absl::StatusOr<RawMesh> ply = ReadMeshFile(Path("out.ply"));
  ASSERT_TRUE(ply.ok()) << ply.status();
  EXPECT_EQ(testing::ExpectGroupsAndFields(*ply), 4u);
}

}  // namespace
}  // namespace femsimp
