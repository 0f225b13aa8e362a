// The FE check through the server (JobSpec.fe_check): the figures in the Result and printed by
// `femsimp simplify --server ... --fe-check`; the refusals before the upload or the queue; and a
// cancel while CalculiX runs, which kills it, removes its directory and frees the worker.
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "client/args.h"
#include "client/exit_codes.h"
#include "client/remote_run.h"
#include "engine/io/mesh_io.h"
#include "fecheck/tools.h"
#include "gtest/gtest.h"
#include "tests/service/test_util.h"
#include "tests/support/fe_check.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

namespace fs = std::filesystem;

// A 100 x 20 x 10 mm plate.
RawMesh Plate(int cells = 10) { return testing::MakeBox({100, 20, 10}, {cells, cells / 5, 1}); }

v1::JobSpec FeCheckSpec() {
  v1::JobSpec spec;
  spec.set_fe_check(true);
  spec.mutable_fe_check_options()->set_unit_scale(0.001);
  return spec;
}

TEST(ServiceFeCheck, ResultHoldsBothSolids) {
  SKIP_WITHOUT_FE_TOOLS();
  testing::InProcessServer s;
  grpc::ClientContext ctx;
  const cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, FeCheckSpec(), Plate());
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  ASSERT_TRUE(out.result.has_fe_check());
  const v1::FeCheckReport& r = out.result.fe_check();
  EXPECT_EQ(r.options().unit_scale(), 0.001);
  EXPECT_EQ(r.options().youngs_modulus(), 210e9);  // the defaults, filled in
  EXPECT_EQ(r.options().poisson_ratio(), 0.3);
  for (const v1::FeSolid* solid : {&r.input(), &r.output()}) {
    EXPECT_NEAR(solid->volume(), 2e-5, 1e-11);
    EXPECT_NEAR(solid->mass(), 7850 * 2e-5, 1e-8);
    ASSERT_EQ(solid->centroid_size(), 3);
    EXPECT_NEAR(solid->centroid(0), 0.05, 1e-9);
    EXPECT_EQ(solid->principal_moments_size(), 3);
    EXPECT_EQ(solid->frequencies_hz_size(), 6);
    EXPECT_EQ(solid->rigid_modes(), 6u);
  }
  EXPECT_EQ(r.input().surface_faces(), Plate().num_faces());
  EXPECT_EQ(r.output().surface_faces(), out.result.output_faces());
}

// A block standing on the plate, the two exported apart: the server's check meshes each body on
// its own (not bonded) and says so in both solids' figures.
TEST(ServiceFeCheck, TouchingBodiesAreMeshedApart) {
  SKIP_WITHOUT_FE_TOOLS();
  RawMesh stacked = Plate();
  testing::Append(stacked, testing::MakeBox({20, 10, 10}, {3, 2, 2}), {10.5f, 5.25f, 10.0f});
  testing::InProcessServer s;
  grpc::ClientContext ctx;
  const cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, FeCheckSpec(), stacked);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_GT(out.result.output_crossings().overlaps().pairs(), 0u);
  for (const v1::FeSolid* solid :
       {&out.result.fe_check().input(), &out.result.fe_check().output()}) {
    EXPECT_EQ(solid->bodies_meshed_apart(), 2u);
    EXPECT_EQ(solid->components(), 2u);
    EXPECT_EQ(solid->rigid_modes(), 12u);
    EXPECT_NEAR(solid->volume(), 2.2e-5, 1e-11);
  }
}

TEST(ServiceFeCheck, RemoteCliPrintsIt) {
  SKIP_WITHOUT_FE_TOOLS();
  testing::InProcessServer s;
  const std::string dir = testing::MakeTempDir("service_fe_check_cli");
  const std::string in = dir + "/plate.off", out = dir + "/out.off";
  ASSERT_TRUE(WriteMeshFile(in, Plate()).ok());
  absl::StatusOr<cli::Command> cmd =
      cli::ParseCommandLine({"femsimp", "simplify", in, out, "--server", s.address(), "--quiet",
                             "--fe-check", "--unit-scale", "0.001", "--density", "2700"});
  ASSERT_TRUE(cmd.ok()) << cmd.status();
  ::testing::internal::CaptureStdout();
  const int code = cli::RunRemote(cmd->simplify);
  const std::string printed = ::testing::internal::GetCapturedStdout();
  ASSERT_EQ(code, cli::kExitOk) << printed;
  EXPECT_HAS(printed,
             "FE check: tetgen + CalculiX C3D10, free-free; E = 2.1e+11 Pa, nu = 0.3, "
             "rho = 2700 kg/m^3, 0.001 m per model unit");
  EXPECT_HAS(printed, "mass [kg]                    0.054            0.054");
  EXPECT_HAS(printed, "frequency 6 [Hz]");
  fs::remove_all(dir);
}

TEST(ServiceFeCheck, RefusedBeforeTheJobRuns) {
  SKIP_WITHOUT_FE_TOOLS();
  testing::InProcessServer s;
  {  // options out of range: before the upload
    v1::JobSpec spec = FeCheckSpec();
    spec.mutable_fe_check_options()->set_poisson_ratio(0.7);
    grpc::ClientContext ctx;
    const cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, Plate());
    EXPECT_EQ(out.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_HAS(out.status.error_message(),
               "spec.fe_check_options: poisson_ratio = 0.7 is out of range: must be in (-1, 0.5)");
  }
  {  // an open input: before the job queues
    RawMesh open = Plate();
    open.triangles.resize(open.triangles.size() - 3 * 40);  // no top: too large a hole to fill
    grpc::ClientContext ctx;
    const cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, FeCheckSpec(), open);
    EXPECT_EQ(out.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_HAS(out.status.error_message(),
               "fe_check: the input (as repaired): the surface is not closed");
  }
  {  // no tools on the server's PATH (the in-process server shares ours)
    const std::string saved = std::getenv("PATH");
    setenv("PATH", "/nonexistent", 1);
    grpc::ClientContext ctx;
    const cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, FeCheckSpec(), Plate());
    setenv("PATH", saved.c_str(), 1);
    EXPECT_EQ(out.status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
    EXPECT_HAS(out.status.error_message(), "tetgen (Debian package tetgen)");
    EXPECT_HAS(out.status.error_message(), "ccx (Debian package calculix-ccx)");
  }
}

// The job's temporary directory with CalculiX's deck in it, once there is one.
bool SolverRunningIn(const std::string& tmp) {
  for (const fs::directory_entry& e : fs::directory_iterator(tmp))
    if (fs::exists(e.path() / "modal.inp")) return true;
  return false;
}

TEST(ServiceFeCheck, CancelKillsTheSolverAndFreesTheWorker) {
  SKIP_WITHOUT_FE_TOOLS();
  const std::string tmp = testing::MakeTempDir("service_fe_check_tmp");
  setenv("TMPDIR", tmp.c_str(), 1);  // where the in-process server's check makes its directory
  testing::InProcessServer s(testing::OneWorkerConfig());
  // A beam whose analysis takes seconds (~6,500 tetrahedra): the cancel lands while ccx runs.
  const RawMesh beam = testing::MakeBox({1000, 40, 40}, {100, 4, 4});
  grpc::ClientContext ctx;
  std::string id;
  cli::RemoteCallbacks cb;
  std::atomic<bool> accepted{false};
  cb.on_accepted = [&](const v1::Accepted& a) {
    id = a.job_id();
    accepted = true;
  };
  cli::RemoteOutcome out;
  std::thread call([&] { out = cli::RemoteSimplify(s.stub(), ctx, FeCheckSpec(), beam, cb); });
  bool running = false;
  for (int i = 0; i < 60000 && !running; ++i) {  // a minute at most
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    running = accepted && SolverRunningIn(tmp);
  }
  EXPECT_TRUE(running) << "CalculiX never started";
  if (running) {
    grpc::ClientContext cancel_ctx;
    v1::CancelJobRequest req;
    req.set_job_id(id);
    v1::CancelJobResponse resp;
    ASSERT_TRUE(s.stub().CancelJob(&cancel_ctx, req, &resp).ok());
    EXPECT_EQ(resp.previous_state(), v1::JOB_STATE_RUNNING);
  }
  call.join();
  unsetenv("TMPDIR");
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::CANCELLED) << out.status.error_message();
  EXPECT_TRUE(fs::is_empty(tmp)) << "the check's directory is left in " << tmp;
  testing::ExpectWorkerFree(s);
  fs::remove_all(tmp);
}

}  // namespace
}  // namespace femsimp
