// The service end to end, in process on loopback ports.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include "engine/mesh.h"
#include "grpcpp/create_channel.h"
#include "grpcpp/security/credentials.h"
#include "gtest/gtest.h"
#include "proto/wire.h"
#include "server/memory_budget.h"
#include "tests/service/test_util.h"

namespace femsimp {
namespace {

using testing::InProcessServer;
using testing::RatioSpec;

v1::SimplifyRequest SpecRequest(uint64_t vertices, uint64_t faces,
                                v1::JobSpec spec = RatioSpec(0.5)) {
  v1::SimplifyRequest r;
  *r.mutable_spec() = std::move(spec);
  r.mutable_spec()->set_vertex_count(vertices);
  r.mutable_spec()->set_face_count(faces);
  return r;
}

// Waits until the job is RUNNING (true) or finished / timed out (false).
bool WaitRunning(v1::Simplifier::Stub& stub, const std::string& id) {
  std::optional<v1::JobInfo> info = testing::WaitWhile(stub, id, v1::JOB_STATE_QUEUED);
  return info && info->state() == v1::JOB_STATE_RUNNING;
}

TEST(Service, FandiskRoundTrip) {
  InProcessServer s;
  RawMesh in = testing::LoadTestMesh("fandisk.off");
  ASSERT_GT(in.num_vertices(), 0u);
  grpc::ClientContext ctx;
  int progress = 0;
  cli::RemoteCallbacks cb;
  cb.on_progress = [&](const v1::Progress& p) {
    ++progress;
    EXPECT_EQ(p.rejections().size(), static_cast<size_t>(Reject::kCount));
  };
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), in, cb);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  // Every pass is reported, also the last one that ends the job (it raced the result once).
  EXPECT_EQ(progress, static_cast<int>(out.result.passes()));
  EXPECT_GT(progress, 0);
  EXPECT_FALSE(out.job_id.empty());
  EXPECT_LT(out.output.num_vertices(), in.num_vertices());
  EXPECT_EQ(out.result.output_vertices(), out.output.num_vertices());
  auto mesh = Mesh::Build(out.output);
  EXPECT_TRUE(mesh.ok()) << mesh.status();

  grpc::ClientContext ictx;
  v1::ServerInfoResponse info;
  ASSERT_TRUE(s.stub().ServerInfo(&ictx, {}, &info).ok());
  EXPECT_EQ(info.queue_capacity(), 16u);
  grpc::ClientContext lctx;
  v1::ListJobsRequest lreq;
  lreq.set_include_finished(true);
  v1::ListJobsResponse list;
  ASSERT_TRUE(s.stub().ListJobs(&lctx, lreq, &list).ok());
  ASSERT_EQ(list.jobs_size(), 1);
  EXPECT_EQ(list.jobs(0).job_id(), out.job_id);
  EXPECT_EQ(list.jobs(0).state(), v1::JOB_STATE_SUCCEEDED);
}

// GetJob and CancelJob refuse an id that cannot be one (over 64 bytes, or not printable ASCII)
// without echoing it; an unknown well-formed id is NOT_FOUND.
TEST(Service, MalformedJobIdsAreRefusedWithoutEcho) {
  InProcessServer s;
  const std::string huge(1 << 20, 'a');
  for (const std::string& id : {huge, std::string("abc\ndef")}) {
    grpc::ClientContext c1, c2;
    v1::GetJobRequest get;
    get.set_job_id(id);
    v1::JobInfo info;
    const grpc::Status g = s.stub().GetJob(&c1, get, &info);
    EXPECT_EQ(g.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_LT(g.error_message().size(), 200u);
    EXPECT_EQ(g.error_message().find(id), std::string::npos);
    v1::CancelJobRequest cancel;
    cancel.set_job_id(id);
    v1::CancelJobResponse resp;
    EXPECT_EQ(s.stub().CancelJob(&c2, cancel, &resp).error_code(),
              grpc::StatusCode::INVALID_ARGUMENT);
  }
  grpc::ClientContext c;
  v1::GetJobRequest get;
  get.set_job_id("0123456789abcdef0123456789abcdef");
  v1::JobInfo info;
  EXPECT_EQ(s.stub().GetJob(&c, get, &info).error_code(), grpc::StatusCode::NOT_FOUND);
}

// A second server on a port already served fails to start instead of sharing it.
TEST(Service, SecondServerOnATakenPortFails) {
  InProcessServer first;
  server::ServerConfig config = testing::TestConfig();
  config.listen = first.address();
  config.metrics_listen = "";
  server::FemsimpServer second(config);
  const absl::Status started = second.Start();
  EXPECT_FALSE(started.ok());
  EXPECT_NE(std::string(started.message()).find(first.address()), std::string::npos)
      << started.message();
}

// A vertex target beyond the documented range (up to 2^64 - 1) is refused by name; it used to
// wrap to 0 ("no target") and simplify as far as the criteria allow.
TEST(Service, HugeVertexTargetIsOutOfRange) {
  InProcessServer s;
  RawMesh in = testing::LoadTestMesh("fandisk.off");
  v1::JobSpec spec;
  spec.mutable_options()->set_target_vertices(~uint64_t{0});
  grpc::ClientContext ctx;
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, in, {});
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(out.status.error_message().find("target_vertices"), std::string::npos)
      << out.status.error_message();
  ExpectWorkerFree(s);
}

// An upload that stalls (nothing sent for --upload_idle_seconds), or that is not done by
// --upload_deadline_seconds, is cancelled: its queue slot is freed (one slot here: the next job
// gets it), and the job's record says why.
TEST(Service, StalledUploadsAreCancelledAndTheirSlotsFreed) {
  for (const bool idle : {true, false}) {
    server::ServerConfig config = testing::OneWorkerConfig();
    config.queue_capacity = 1;
    config.upload_idle_seconds = idle ? 0.3 : 0.0;
    config.upload_deadline_seconds = idle ? 0.0 : 0.6;
    InProcessServer s(config);
    grpc::ClientContext ctx;
    ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    auto stream = s.stub().Simplify(&ctx);
    v1::SimplifyRequest first;
    *first.mutable_spec() = RatioSpec(0.5);
    first.mutable_spec()->set_vertex_count(1000);
    first.mutable_spec()->set_face_count(2000);
    ASSERT_TRUE(stream->Write(first));
    v1::SimplifyResponse resp;
    ASSERT_TRUE(stream->Read(&resp));
    ASSERT_TRUE(resp.has_accepted());
    const std::string id = resp.accepted().job_id();
    const auto start = std::chrono::steady_clock::now();
    if (!idle) {  // a trickle: one empty chunk now and then, never the mesh
      for (int i = 0; i < 20; ++i) {
        v1::SimplifyRequest chunk;
        chunk.mutable_chunk();
        if (!stream->Write(chunk)) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
    }
    while (stream->Read(&resp)) {
    }
    const grpc::Status ended = stream->Finish();
    EXPECT_FALSE(ended.ok());
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              10.0);
    // The watchdog cancels the call first and the handler closes the job when it sees that:
    // the client's call can end a moment before the job's record does.
    std::optional<v1::JobInfo> info = testing::GetJob(s.stub(), id);
    for (int i = 0; i < 100 && info.has_value() && info->status_code().empty(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      info = testing::GetJob(s.stub(), id);
    }
    ASSERT_TRUE(info.has_value());
    EXPECT_EQ(info->status_code(), "DEADLINE_EXCEEDED");
    EXPECT_NE(info->status_message().find(idle ? "upload idle" : "upload not done"),
              std::string::npos)
        << info->status_message();
    ExpectWorkerFree(s);
  }
}

// A client that stops reading its result does not hold the output mesh: after
// --result_idle_seconds without a write going through, the call is cancelled, counted as
// DEADLINE_EXCEEDED, the job's record says the result was not delivered, and the server is
// whole.
TEST(Service, UnreadResultIsDropped) {
  server::ServerConfig config = testing::OneWorkerConfig();
  config.result_idle_seconds = 0.5;
  InProcessServer s(config);
  const RawMesh big = testing::MakeTorus(500, 500);  // an output of ~8 MB: beyond the windows
  // Without BDP probing the client's window stays at gRPC's 4 MiB; with it, a server slow to
  // answer pings (sanitizers) can grow the window past the result, which then fits unread.
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  auto stub = v1::Simplifier::NewStub(
      grpc::CreateCustomChannel(s.address(), grpc::InsecureChannelCredentials(), args));
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  auto stream = stub->Simplify(&ctx);
  v1::SimplifyRequest first;
  *first.mutable_spec() = RatioSpec(0.95);
  first.mutable_spec()->set_vertex_count(big.num_vertices());
  first.mutable_spec()->set_face_count(big.num_faces());
  ASSERT_TRUE(stream->Write(first));
  wire::ForEachChunk(big, [&](v1::MeshChunk& chunk) {
    v1::SimplifyRequest r;
    r.mutable_chunk()->Swap(&chunk);
    return stream->Write(r);
  });
  stream->WritesDone();
  v1::SimplifyResponse resp;
  ASSERT_TRUE(stream->Read(&resp));
  ASSERT_TRUE(resp.has_accepted());
  // Read nothing more: the server's writes of the result stall, and the watchdog ends the call.
  std::optional<double> dropped;
  for (int i = 0; i < 600 && !dropped; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto m = testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"));
    if (const auto it = m.find("femsimp_jobs_total{status=\"DEADLINE_EXCEEDED\"}"); it != m.end())
      dropped = it->second;
  }
  ASSERT_TRUE(dropped.has_value()) << "the unread result was not dropped within 30 s";
  EXPECT_EQ(*dropped, 1);
  while (stream->Read(&resp)) {
  }
  EXPECT_FALSE(stream->Finish().ok());
  grpc::ClientContext list_ctx;
  v1::ListJobsRequest list;
  list.set_include_finished(true);
  v1::ListJobsResponse jobs;
  ASSERT_TRUE(s.stub().ListJobs(&list_ctx, list, &jobs).ok());
  ASSERT_EQ(jobs.jobs_size(), 1);
  EXPECT_EQ(jobs.jobs(0).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(jobs.jobs(0).status_code(), "DEADLINE_EXCEEDED");
  EXPECT_NE(jobs.jobs(0).status_message().find("result not delivered"), std::string::npos)
      << jobs.jobs(0).status_message();
  ExpectWorkerFree(s);
}

TEST(Service, FaceGroupsAndFieldsComeBack) {
  InProcessServer s;
  const RawMesh in = testing::WithGroupsAndFields(testing::MakeTorus(60, 40));
  v1::JobSpec spec = RatioSpec(0.5);
  // Fidelity options travel and pass validation (what the engine makes of them is its tests').
  spec.mutable_options()->set_cost(v1::COST_KIND_QUADRIC);
  spec.mutable_options()->set_feature_angle_deg(40);
  spec.mutable_options()->set_max_field_change(0.5);
  grpc::ClientContext ctx;
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, in);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_LT(out.output.num_faces(), in.num_faces());
  EXPECT_TRUE(out.result.has_face_groups());
  ASSERT_EQ(out.result.face_field_names_size(), 2);
  EXPECT_EQ(out.result.face_field_names(0), "pressure");
  EXPECT_EQ(out.result.face_field_names(1), "heat_flux");
  EXPECT_EQ(testing::ExpectGroupsAndFields(out.output), 4u);
  EXPECT_TRUE(Mesh::Build(out.output).ok());
}

TEST(Service, LargeMeshNeedsChunking) {
  InProcessServer s;
  RawMesh in = testing::MakeTorus(500, 500);  // 250k vertices: 3 MB + 6 MB of arrays
  ASSERT_GT(in.positions.size() * 4 + in.triangles.size() * 4, 4u << 20);
  grpc::ClientContext ctx;
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), in);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_LT(out.output.num_vertices(), in.num_vertices());
  EXPECT_GT(out.chunks_received, 0);
  EXPECT_TRUE(Mesh::Build(out.output).ok());
}

TEST(Service, CancelRunningJobThenWorkerTakesNext) {
  server::ServerConfig config = testing::TestConfig();
  config.workers = 1;
  config.threads_per_job = 1;
  InProcessServer s(config);
  RawMesh big = testing::MakeTorus(1000, 1000);
  v1::JobSpec spec;
  spec.mutable_options()->set_target_vertices(50);
  spec.mutable_options()->set_threads(1);
  grpc::ClientContext ctx;
  std::atomic<bool> cancelled_at_running{false};
  std::chrono::steady_clock::time_point cancel_time;
  std::thread canceller;
  cli::RemoteCallbacks cb;
  cb.on_accepted = [&](const v1::Accepted& a) {
    canceller = std::thread([&, id = a.job_id()] {
      if (WaitRunning(s.stub(), id)) {
        cancel_time = std::chrono::steady_clock::now();
        cancelled_at_running = true;
        ctx.TryCancel();
      }
    });
  };
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, big, cb, false);
  canceller.join();
  ASSERT_TRUE(cancelled_at_running) << "job was never seen running";
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::CANCELLED);
  // The server side ends the job within a pass (here: well under the job's run time).
  std::optional<v1::JobInfo> info =
      testing::WaitWhile(s.stub(), out.job_id, v1::JOB_STATE_RUNNING, 5.0);
  ASSERT_TRUE(info) << "job still running 5 s after the cancel";
  EXPECT_EQ(info->state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(info->status_code(), "CANCELLED");

  // The single worker is free again.
  grpc::ClientContext ctx2;
  cli::RemoteOutcome next =
      cli::RemoteSimplify(s.stub(), ctx2, RatioSpec(0.5), testing::LoadTestMesh("fandisk.off"));
  EXPECT_TRUE(next.status.ok()) << next.status.error_message();
}

TEST(Service, CancelJobRpc) {
  server::ServerConfig config = testing::TestConfig();
  config.workers = 1;
  config.threads_per_job = 1;
  InProcessServer s(config);
  RawMesh big = testing::MakeTorus(1000, 1000);
  v1::JobSpec spec;
  spec.mutable_options()->set_target_vertices(50);
  grpc::ClientContext ctx;
  std::thread canceller;
  cli::RemoteCallbacks cb;
  cb.on_accepted = [&](const v1::Accepted& a) {
    canceller = std::thread([&, id = a.job_id()] {
      WaitRunning(s.stub(), id);
      grpc::ClientContext c;
      v1::CancelJobRequest req;
      req.set_job_id(id);
      v1::CancelJobResponse resp;
      EXPECT_TRUE(s.stub().CancelJob(&c, req, &resp).ok());
    });
  };
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, big, cb, false);
  canceller.join();
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::CANCELLED) << out.status.error_message();
  EXPECT_NE(out.status.error_message().find("CancelJob"), std::string::npos);
}

TEST(Service, DeadlineExceeded) {
  InProcessServer s;
  RawMesh big = testing::MakeTorus(1000, 1000);
  v1::JobSpec spec;
  spec.mutable_options()->set_target_vertices(50);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(300));
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, big, {}, false);
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED);
  // The server is still serving.
  grpc::ClientContext ctx2;
  cli::RemoteOutcome next =
      cli::RemoteSimplify(s.stub(), ctx2, RatioSpec(0.5), testing::LoadTestMesh("fandisk.off"));
  EXPECT_TRUE(next.status.ok()) << next.status.error_message();
}

TEST(Service, QueueFullIsResourceExhaustedWithPushback) {
  server::ServerConfig config = testing::TestConfig();
  config.workers = 1;
  config.queue_capacity = 1;
  InProcessServer s(config);
  // A call that sent its spec holds the only queue slot while it "uploads".
  grpc::ClientContext hold_ctx;
  auto hold = s.stub().Simplify(&hold_ctx);
  ASSERT_TRUE(hold->Write(SpecRequest(3, 1)));
  v1::SimplifyResponse accepted;
  ASSERT_TRUE(hold->Read(&accepted));
  ASSERT_TRUE(accepted.has_accepted());

  grpc::ClientContext ctx;
  cli::RemoteOutcome out =
      cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), testing::LoadTestMesh("fandisk.off"));
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(out.status.error_message().find("queue is full"), std::string::npos);
  EXPECT_EQ(out.retry_pushback_ms, 250);

  hold_ctx.TryCancel();
  hold->Finish();
}

// Memory admission by the declared size (issue 15, item 2).
uint64_t AdmittedBytes(InProcessServer& s) {
  return static_cast<uint64_t>(testing::ParseMetrics(
      testing::HttpGet(s.server().metrics_port(), "/metrics"))["femsimp_memory_admitted_bytes"]);
}

TEST(Service, JobAboveTheMemoryBudgetAloneIsRefusedBeforeItsUpload) {
  server::ServerConfig config = testing::TestConfig();
  config.memory_budget_mib = 64;
  InProcessServer s(config);
  const uint64_t need =
      server::EstimateJobBytes(1'000'000, 2'000'000, SimplifyOptions{});  // ~554 MiB
  ASSERT_GT(need, uint64_t{64} << 20);
  // Only the spec is sent, and the stream stays open: the answer comes before any chunk.
  grpc::ClientContext ctx;
  auto call = s.stub().Simplify(&ctx);
  ASSERT_TRUE(call->Write(SpecRequest(1'000'000, 2'000'000)));
  v1::SimplifyResponse resp;
  EXPECT_FALSE(call->Read(&resp)) << "accepted: " << resp.ShortDebugString();
  const grpc::Status st = call->Finish();
  EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(st.error_message(),
            absl::StrCat("the job needs an estimated ", (need + (1 << 20) - 1) >> 20,
                         " MiB (1000000 vertices, 2000000 faces declared), above this server's "
                         "memory budget of 64 MiB (--memory_budget_mib)"));
  // Never admissible here: no pushback, so clients do not retry it.
  EXPECT_EQ(ctx.GetServerTrailingMetadata().count("grpc-retry-pushback-ms"), 0u);
  EXPECT_EQ(AdmittedBytes(s), 0u);
}

TEST(Service, JobThatDoesNotFitBesideTheAdmittedOnesGetsPushbackUntilMemoryFrees) {
  const uint64_t big = server::EstimateJobBytes(200'000, 400'000, SimplifyOptions{});
  server::ServerConfig config = testing::TestConfig();
  // One big job fits, two do not; fandisk fits beside one.
  config.memory_budget_mib = (big + big / 2) >> 20;
  InProcessServer s(config);
  EXPECT_EQ(testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(),
                                                   "/metrics"))["femsimp_memory_budget_bytes"],
            static_cast<double>(config.memory_budget_mib << 20));
  // A call that sent its spec holds its estimate while it "uploads".
  grpc::ClientContext hold_ctx;
  auto hold = s.stub().Simplify(&hold_ctx);
  ASSERT_TRUE(hold->Write(SpecRequest(200'000, 400'000)));
  v1::SimplifyResponse accepted;
  ASSERT_TRUE(hold->Read(&accepted));
  ASSERT_TRUE(accepted.has_accepted());
  EXPECT_EQ(AdmittedBytes(s), big);

  grpc::ClientContext second_ctx;
  auto second = s.stub().Simplify(&second_ctx);
  ASSERT_TRUE(second->Write(SpecRequest(200'000, 400'000)));
  v1::SimplifyResponse resp;
  EXPECT_FALSE(second->Read(&resp));
  const grpc::Status refused = second->Finish();
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused.error_message().find("not enough memory now"), std::string::npos)
      << refused.error_message();
  EXPECT_NE(refused.error_message().find("jobs admitted: 1, holding "), std::string::npos)
      << refused.error_message();
  const auto trailer = second_ctx.GetServerTrailingMetadata().find("grpc-retry-pushback-ms");
  ASSERT_NE(trailer, second_ctx.GetServerTrailingMetadata().end());
  EXPECT_EQ(std::string(trailer->second.data(), trailer->second.size()), "250");

  // Admission is by the sum of the estimates, not a count: a small job runs beside the big one.
  const RawMesh fandisk = testing::LoadTestMesh("fandisk.off");
  {
    grpc::ClientContext ctx;
    cli::RemoteOutcome small = cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), fandisk);
    EXPECT_TRUE(small.status.ok()) << small.status.error_message();
  }
  EXPECT_EQ(AdmittedBytes(s), big);  // the small job's estimate was given back with its call
  {  // and a failed job's (an index past the vertices, refused after the upload)
    RawMesh bad;
    bad.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bad.triangles = {0, 1, 7};
    grpc::ClientContext ctx;
    EXPECT_EQ(cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), bad).status.error_code(),
              grpc::StatusCode::INVALID_ARGUMENT);
  }
  EXPECT_EQ(AdmittedBytes(s), big);
  // The held call ends: its estimate is given back, and the big job is admitted again.
  hold_ctx.TryCancel();
  hold->Finish();
  for (int i = 0; i < 500 && AdmittedBytes(s) != 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(AdmittedBytes(s), 0u);
  grpc::ClientContext again_ctx;
  auto again = s.stub().Simplify(&again_ctx);
  ASSERT_TRUE(again->Write(SpecRequest(200'000, 400'000)));
  ASSERT_TRUE(again->Read(&resp));
  EXPECT_TRUE(resp.has_accepted());
  again_ctx.TryCancel();
  again->Finish();
}

// The cell back end runs a host thread and a local store per SPE: a job may not ask for more
// than the server allows, and is told which limit (and flag) it met before anything uploads.
TEST(Service, CellBackEndWithinTheServersLimits) {
  server::ServerConfig config = testing::TestConfig();
  config.max_spes = 8;
  config.max_cell_local_store_mib = 4;
  InProcessServer s(config);
  const RawMesh mesh = testing::LoadTestMesh("fandisk.off");
  const auto run = [&](int spes, int local_store_kib) {
    v1::JobSpec spec = RatioSpec(0.5);
    spec.mutable_options()->set_backend(v1::BACKEND_CELL);
    spec.mutable_options()->mutable_cell()->set_spes(spes);
    spec.mutable_options()->mutable_cell()->set_local_store_kib(local_store_kib);
    grpc::ClientContext ctx;
    return cli::RemoteSimplify(s.stub(), ctx, spec, mesh).status;
  };
  const grpc::Status too_many = run(9, 256);
  EXPECT_EQ(too_many.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(too_many.error_message(),
            "spec.options.cell.spes: 9 is above this server's limit of 8 (--max_spes)");
  const grpc::Status too_big = run(8, 1024);
  EXPECT_EQ(too_big.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(too_big.error_message(),
            "spec.options.cell: 8 SPEs x 1024 KiB of local store = 8 MiB is above this server's "
            "limit of 4 MiB (--max_cell_local_store_mib)");
  const grpc::Status within = run(8, 512);
  EXPECT_TRUE(within.ok()) << within.error_message();
}

TEST(Service, MalformedStreamsAreInvalidArgument) {
  server::ServerConfig config = testing::TestConfig();
  config.max_vertices = 1'000'000;
  InProcessServer s(config);
  v1::SimplifyRequest tri;
  for (float x : {0, 0, 0, 1, 0, 0, 0, 1, 0}) tri.mutable_chunk()->add_positions(x);
  for (uint32_t i : {0u, 1u, 2u}) tri.mutable_chunk()->add_indices(i);
  v1::SimplifyRequest nan = tri;
  nan.mutable_chunk()->set_positions(4, std::nanf(""));
  v1::SimplifyRequest out_of_range = tri;
  out_of_range.mutable_chunk()->set_indices(2, 7);
  v1::SimplifyRequest degenerate = tri;
  degenerate.mutable_chunk()->set_indices(2, 1);
  v1::JobSpec bad_angle = RatioSpec(0.5);
  bad_angle.mutable_options()->set_min_angle_deg(80);
  v1::JobSpec bad_ratio = RatioSpec(1.5);
  v1::JobSpec bad_tolerance = RatioSpec(0.5);
  bad_tolerance.mutable_options()->set_tolerance_relative(3);
  v1::JobSpec five_fields = RatioSpec(0.5);
  for (const char* n : {"a", "b", "c", "d", "e"}) five_fields.add_face_field_names(n);
  v1::JobSpec field_p = RatioSpec(0.5);
  field_p.add_face_field_names("p");
  v1::JobSpec two_origin = RatioSpec(0.5);
  two_origin.add_origin(1e6);
  two_origin.add_origin(2e6);
  v1::JobSpec nan_origin = RatioSpec(0.5);
  for (double x : {1e6, std::nan(""), 0.0}) nan_origin.add_origin(x);
  v1::SimplifyRequest tri_nan_p = tri;
  tri_nan_p.mutable_chunk()->add_face_fields()->add_values(std::nanf(""));

  struct Case {
    const char* name;
    std::vector<v1::SimplifyRequest> requests;
    grpc::StatusCode code;
    const char* message;
  } cases[] = {
      {"empty stream", {}, grpc::StatusCode::INVALID_ARGUMENT, "before the job spec"},
      {"no spec first", {tri}, grpc::StatusCode::INVALID_ARGUMENT, "spec must come first"},
      {"two specs",
       {SpecRequest(3, 1), SpecRequest(3, 1)},
       grpc::StatusCode::INVALID_ARGUMENT,
       "second job spec"},
      {"chunk past declared",
       {SpecRequest(3, 1), tri, tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "past the declared"},
      {"missing chunks", {SpecRequest(3, 1)}, grpc::StatusCode::INVALID_ARGUMENT, "ended early"},
      {"index out of range",
       {SpecRequest(3, 1), out_of_range},
       grpc::StatusCode::INVALID_ARGUMENT,
       "references vertex 7"},
      {"NaN", {SpecRequest(3, 1), nan}, grpc::StatusCode::INVALID_ARGUMENT, "non-finite"},
      {"parameter out of range",
       {SpecRequest(3, 1, bad_angle), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "min_angle"},
      {"ratio out of range",
       {SpecRequest(3, 1, bad_ratio), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "ratio"},
      {"tolerance out of range",
       {SpecRequest(3, 1, bad_tolerance), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "tolerance_relative = 3 is out of range"},
      {"too many fields",
       {SpecRequest(3, 1, five_fields), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "spec: face_field_names: 5 face fields, at most 3"},
      {"origin of two coordinates",
       {SpecRequest(3, 1, two_origin), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "spec: origin: 2 coordinates (expected none or x, y, z)"},
      {"origin not finite",
       {SpecRequest(3, 1, nan_origin), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "spec: origin: coordinate 1 is not finite (nan)"},
      {"field values missing",
       {SpecRequest(3, 1, field_p), tri},
       grpc::StatusCode::INVALID_ARGUMENT,
       "received 0 of 1 values of face field 'p'"},
      {"field value NaN",
       {SpecRequest(3, 1, field_p), tri_nan_p},
       grpc::StatusCode::INVALID_ARGUMENT,
       "face field 'p': face 0 has a non-finite value"},
      {"nothing left after repair",
       {SpecRequest(3, 1), degenerate},
       grpc::StatusCode::INVALID_ARGUMENT,
       "invalid mesh: mesh is empty after repair: all 1 facets were degenerate"},
      {"empty mesh", {SpecRequest(0, 0)}, grpc::StatusCode::INVALID_ARGUMENT, "vertex_count"},
      {"over max_vertices",
       {SpecRequest(2'000'000, 1)},
       grpc::StatusCode::RESOURCE_EXHAUSTED,
       "max_vertices"},
  };
  for (const Case& c : cases) {
    grpc::Status st = testing::SendRaw(s.stub(), c.requests);
    EXPECT_EQ(st.error_code(), c.code) << c.name << ": " << st.error_message();
    EXPECT_NE(st.error_message().find(c.message), std::string::npos)
        << c.name << ": " << st.error_message();
  }
}

TEST(Service, MessageOverMaxRequestBytes) {
  server::ServerConfig config = testing::TestConfig();
  config.max_request_bytes = 256 << 10;
  InProcessServer s(config);
  RawMesh torus = testing::MakeTorus(200, 200);  // 40k vertices = 480 KB in one chunk
  std::vector<v1::SimplifyRequest> reqs = {SpecRequest(torus.num_vertices(), torus.num_faces())};
  reqs.emplace_back();
  reqs.back().mutable_chunk()->mutable_positions()->Add(torus.positions.begin(),
                                                        torus.positions.end());
  grpc::Status st = testing::SendRaw(s.stub(), reqs);
  EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << st.error_message();
}

TEST(Service, SixteenConcurrentJobs) {
  InProcessServer s;
  RawMesh in = testing::LoadTestMesh("fandisk.off");
  std::vector<std::thread> clients;
  std::atomic<int> ok{0};
  for (int i = 0; i < 16; ++i)
    clients.emplace_back([&] {
      grpc::ClientContext ctx;
      cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.3), in);
      EXPECT_TRUE(out.status.ok()) << out.status.error_message();
      if (out.status.ok() && out.output.num_vertices() < in.num_vertices()) ++ok;
    });
  for (auto& t : clients) t.join();
  EXPECT_EQ(ok.load(), 16);
}

// Clients that connect to /metrics and send nothing do not hold it: a scrape right after four
// such connections is answered at once (with civetweb's defaults it waited for their 30 s
// request timeout).
TEST(Service, IdleConnectionsDoNotBlockMetrics) {
  InProcessServer s;
  const int port = s.server().metrics_port();
  ASSERT_GT(port, 0);
  std::vector<int> idle;
  for (int i = 0; i < 4; ++i) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    ASSERT_GE(fd, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    idle.push_back(fd);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // accepted, waiting for a request
  const auto start = std::chrono::steady_clock::now();
  const auto metrics = testing::ParseMetrics(testing::HttpGet(port, "/metrics"));
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int fd : idle) close(fd);
  EXPECT_EQ(metrics.count("femsimp_queue_depth"), 1u);
  EXPECT_LT(waited, 10.0);
}

// Each stage of a job on the server has its histogram, labelled by stage and back end: one job,
// one observation of each; the stages the call runs one after the other fit in the call's time.
TEST(Service, StageHistogramsCountEachStageOfAJobOnce) {
  InProcessServer s;
  RawMesh in = testing::LoadTestMesh("fandisk.off");
  const auto start = std::chrono::steady_clock::now();
  grpc::ClientContext ctx;
  ASSERT_TRUE(cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), in).status.ok());
  const double call =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto metrics =
      testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"));
  const auto find = [&](const std::string& series, const std::string& stage) {
    for (const auto& [k, v] : metrics)
      if (k.rfind(series + "{", 0) == 0 && k.find("backend=\"native\"") != std::string::npos &&
          k.find("stage=\"" + stage + "\"") != std::string::npos)
        return v;
    ADD_FAILURE() << "no " << series << " for stage " << stage;
    return -1.0;
  };
  double sequential = 0;
  for (const char* stage : {"upload", "repair", "build", "engine", "encode", "download"}) {
    EXPECT_EQ(find("femsimp_stage_duration_seconds_count", stage), 1) << stage;
    const double seconds = find("femsimp_stage_duration_seconds_sum", stage);
    EXPECT_GE(seconds, 0) << stage;
    if (std::string(stage) != "encode" && std::string(stage) != "download") sequential += seconds;
  }
  EXPECT_GT(find("femsimp_stage_duration_seconds_sum", "engine"), 0);
  EXPECT_LE(sequential, call);
}

TEST(Service, MetricsMove) {
  InProcessServer s;
  ASSERT_GT(s.server().metrics_port(), 0);
  auto before = testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"));
  EXPECT_EQ(before.count("femsimp_jobs_total{status=\"OK\"}"), 0u);
  EXPECT_EQ(before.at("femsimp_queue_depth"), 0);
  RawMesh in = testing::LoadTestMesh("fandisk.off");
  for (int i = 0; i < 2; ++i) {
    grpc::ClientContext ctx;
    ASSERT_TRUE(cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), in).status.ok());
  }
  testing::SendRaw(s.stub(), {});  // one INVALID_ARGUMENT
  auto after = testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"));
  EXPECT_EQ(after.at("femsimp_jobs_total{status=\"OK\"}"), 2);
  EXPECT_EQ(after.at("femsimp_jobs_total{status=\"INVALID_ARGUMENT\"}"), 1);
  EXPECT_EQ(after.at("femsimp_vertices_in_total"), 2.0 * in.num_vertices());
  EXPECT_GT(after.at("femsimp_vertices_removed_total"), 0);
  EXPECT_GT(after.at("femsimp_passes_total{backend=\"native\"}"), 0);
  EXPECT_EQ(after.at("femsimp_job_duration_seconds_count{backend=\"native\"}"), 2);
  EXPECT_EQ(after.at("femsimp_running_jobs"), 0);
  bool speedup = false;
  for (const auto& [k, v] : after)
    if (k.rfind("femsimp_parallel_speedup_count{", 0) == 0 &&
        k.find("backend=\"native\"") != std::string::npos &&
        k.find("contexts=\"2\"") != std::string::npos)
      speedup = v == 2;
  EXPECT_TRUE(speedup);
}

}  // namespace
}  // namespace femsimp
