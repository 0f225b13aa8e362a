// `femsimp check` and `femsimp simplify --fe-check` (local) on files: the table, the JSON, and
// the exit codes of a mesh that cannot be checked.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "client/args.h"
#include "client/check_cmd.h"
#include "client/exit_codes.h"
#include "client/local_run.h"
#include "fecheck/tools.h"
#include "tests/support/fe_check.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

class CliCheckTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    SKIP_WITHOUT_FE_TOOLS();
    // A 100 x 20 x 10 mm plate, finely and coarsely meshed.
    fine_ = WriteSoup("fine.off", testing::MakeBox({100, 20, 10}, {20, 4, 2}));
    coarse_ = WriteSoup("coarse.off", testing::MakeBox({100, 20, 10}, {10, 2, 1}));
  }

  // Runs `femsimp ARGS...` in process; stdout and stderr captured.
  int Run(std::vector<std::string> args) {
    args.insert(args.begin(), "femsimp");
    absl::StatusOr<cli::Command> cmd = cli::ParseCommandLine(args);
    EXPECT_TRUE(cmd.ok()) << cmd.status();
    if (!cmd.ok()) return -1;
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    const int code = cmd->kind == cli::Command::kCheck ? cli::RunCheck(cmd->check)
                                                       : cli::RunLocal(cmd->simplify);
    out_ = ::testing::internal::GetCapturedStdout();
    err_ = ::testing::internal::GetCapturedStderr();
    return code;
  }

  std::string fine_, coarse_, out_, err_;
};

TEST_F(CliCheckTest, TableAndJson) {
  ASSERT_EQ(Run({"check", fine_, coarse_, "--unit-scale", "0.001", "--json", Path("c.json")}),
            cli::kExitOk)
      << err_;
  EXPECT_HAS(out_, "E = 2.1e+11 Pa, nu = 0.3, rho = 7850 kg/m^3, 0.001 m per model unit");
  EXPECT_HAS(out_, "volume [m^3]                 2e-05            2e-05            ");
  // The ratio is tetgen's (it depends on the surfaces and their numbering), not the check's.
  EXPECT_HAS(out_, "note: the tet meshes differ ");
  EXPECT_HAS(out_, "x in size, so the frequency differences include discretisation error");
  EXPECT_HAS(out_, "frequency 6 [Hz]");
  EXPECT_HAS(out_, "rigid-body modes set apart   6                6");
  // Progress lines on stderr (not a terminal here), one per step.
  EXPECT_HAS(err_, "FE check 1/4: original " + fine_ + ": CalculiX modal analysis");
  EXPECT_HAS(err_, "FE check 4/4: done");
  const std::string json = testing::ReadFileBytes(Path("c.json"));
  EXPECT_HAS(json, "\"unit_scale\": 0.001");
  EXPECT_HAS(json, "\"path\": \"" + fine_ + "\"");
  EXPECT_HAS(json, "\"rigid_modes\": 6");
  EXPECT_HAS(json, "\"worst_frequency\": ");
}

// Bodies exported apart that touch: checked, each body meshed on its own, which the table and
// the JSON say.
TEST_F(CliCheckTest, TouchingBodiesAreCheckedApart) {
  RawMesh stacked = testing::MakeBox({100, 20, 10}, {10, 2, 1});
  testing::Append(stacked, testing::MakeBox({20, 10, 10}, {3, 2, 2}), {10.5f, 5.25f, 10.0f});
  const std::string path = WriteSoup("stacked.off", stacked);
  ASSERT_EQ(Run({"check", path, path, "--unit-scale", "0.001", "--json", Path("c.json")}),
            cli::kExitOk)
      << err_;
  EXPECT_HAS(out_,
             "note: the original surface's 2 bodies touch without sharing faces: each was "
             "tet-meshed on its own, so they are not bonded");
  EXPECT_HAS(out_, "rigid-body modes set apart   12               12");
  EXPECT_HAS(testing::ReadFileBytes(Path("c.json")), "\"bodies_meshed_apart\": 2");
}

TEST_F(CliCheckTest, OpenSurfaceExitsWithInvalidInput) {
  RawMesh open = testing::MakeBox({100, 20, 10}, {10, 2, 1});
  open.triangles.resize(open.triangles.size() - 3 * 40);  // no top: too large a hole to fill
  const std::string path = WriteSoup("open.off", open);
  EXPECT_EQ(Run({"check", fine_, path, "--quiet"}), cli::kExitInputInvalid);
  EXPECT_HAS(err_, "FE check failed: simplified " + path + ": the surface is not closed");
  EXPECT_EQ(Run({"check", fine_, Path("missing.off"), "--quiet"}), cli::kExitInputUnreadable);
}

TEST_F(CliCheckTest, SimplifyWithFeCheck) {
  ASSERT_EQ(Run({"simplify", fine_, Path("out.off"), "--fe-check", "--unit-scale", "0.001",
                 "--quiet", "--stats-json", Path("s.json")}),
            cli::kExitOk)
      << err_;
  EXPECT_HAS(out_, "FE check: tetgen + CalculiX C3D10");
  EXPECT_HAS(out_, "  simplified: " + Path("out.off"));
  EXPECT_HAS(testing::ReadFileBytes(Path("s.json")), "\"fe_check\": {");
}

TEST(CliCheckArgs, MaterialFlagsNeedFeCheck) {
  absl::StatusOr<cli::Command> cmd =
      cli::ParseCommandLine({"femsimp", "simplify", "a.off", "b.off", "--density", "2700"});
  EXPECT_EQ(cmd.status().message(), "--density needs --fe-check");
  cmd = cli::ParseCommandLine({"femsimp", "check", "a.off", "b.off", "--poisson-ratio", "0.5"});
  EXPECT_EQ(cmd.status().message(), "--poisson-ratio = 0.5 is out of range: must be in (-1, 0.5)");
  cmd = cli::ParseCommandLine({"femsimp", "simplify", "a.off", "b.off", "--fe-check",
                               "--fe-threads", "2", "--server", "localhost:1"});
  EXPECT_EQ(cmd.status().message(),
            "--fe-threads is for local runs: a server gives CalculiX the job's threads");
  cmd = cli::ParseCommandLine({"femsimp", "check", "a.off"});
  EXPECT_FALSE(cmd.ok());
}

}  // namespace
}  // namespace femsimp
