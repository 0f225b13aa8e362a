// The client side of scale-out: retries (client/retry.h) with their backoff and pushback
// policy, whole jobs retried against real in-process servers that are full, late or gone; calls
// balanced over several addresses; the `femsimp health` probe; the output check of
// femsimp-load --verify.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "client/health.h"
#include "client/retry.h"
#include "engine/mesh_checks.h"
#include "gtest/gtest.h"
#include "tests/service/test_util.h"

extern char** environ;

namespace femsimp {
namespace {

using cli::RetryDelay;
using cli::RetryPolicy;
using std::chrono::milliseconds;
using testing::InProcessServer;
using testing::RatioSpec;

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(RetryPolicy, BackoffDoublesUpToTheCap) {
  RetryPolicy p;
  p.jitter = 0;
  std::vector<long long> got;
  for (int attempt = 1; attempt <= 8; ++attempt)
    got.push_back(RetryDelay(p, attempt, std::nullopt, 0.5).count());
  EXPECT_EQ(got, (std::vector<long long>{250, 500, 1000, 2000, 4000, 8000, 8000, 8000}));
}

TEST(RetryPolicy, JitterStaysWithinItsBand) {
  RetryPolicy p;                                                // jitter 0.2
  EXPECT_EQ(RetryDelay(p, 2, std::nullopt, 0.0).count(), 400);  // 500 * 0.8
  EXPECT_EQ(RetryDelay(p, 2, std::nullopt, 0.5).count(), 500);
  EXPECT_EQ(RetryDelay(p, 2, std::nullopt, 0.999).count(), 600);  // 500 * 1.2, rounded
  EXPECT_EQ(RetryDelay(p, 20, std::nullopt, 0.0).count(), 6400);  // the cap is jittered too
}

TEST(RetryPolicy, PushbackReplacesBackoffAndIsNeverShortened) {
  RetryPolicy p;
  for (int attempt : {1, 3, 9}) {
    EXPECT_EQ(RetryDelay(p, attempt, 1000, 0.0).count(), 1000);
    EXPECT_LE(RetryDelay(p, attempt, 1000, 0.999).count(), 1200);
    EXPECT_GE(RetryDelay(p, attempt, 1000, 0.999).count(), 1000);
  }
  EXPECT_EQ(RetryDelay(p, 1, 0, 0.7).count(), 0);
  EXPECT_EQ(RetryDelay(p, 1, 30000, 0.0).count(), 30000);  // above max_backoff: still honoured
}

TEST(RetryPolicy, WhatIsRetryable) {
  using grpc::StatusCode;
  EXPECT_TRUE(cli::IsRetryable(StatusCode::UNAVAILABLE, std::nullopt));
  EXPECT_TRUE(cli::IsRetryable(StatusCode::RESOURCE_EXHAUSTED, 250));
  EXPECT_TRUE(cli::IsRetryable(StatusCode::RESOURCE_EXHAUSTED, 0));
  // No pushback: a server limit such as the mesh size, the same on every attempt.
  EXPECT_FALSE(cli::IsRetryable(StatusCode::RESOURCE_EXHAUSTED, std::nullopt));
  EXPECT_FALSE(cli::IsRetryable(StatusCode::RESOURCE_EXHAUSTED, -1));  // server: do not retry
  for (StatusCode c : {StatusCode::OK, StatusCode::CANCELLED, StatusCode::INVALID_ARGUMENT,
                       StatusCode::DEADLINE_EXCEEDED, StatusCode::INTERNAL, StatusCode::DATA_LOSS,
                       StatusCode::UNIMPLEMENTED})
    EXPECT_FALSE(cli::IsRetryable(c, 250)) << cli::GrpcCodeName(c);
}

// A queue that never has room: every attempt is pushed back, and each wait honours it.
TEST(Retry, FullQueueIsRetriedAfterThePushbackThenGivenUp) {
  server::ServerConfig config = testing::TestConfig();
  config.queue_capacity = 0;
  config.retry_pushback_ms = 200;
  InProcessServer s(config);
  cli::RetryOptions options;
  options.policy.max_attempts = 3;
  std::vector<milliseconds> waits;
  options.on_retry = [&](int, const cli::RemoteOutcome& o, milliseconds d) {
    EXPECT_EQ(o.retry_pushback_ms, 200);
    waits.push_back(d);
  };
  cli::RetryCounters counters;
  auto t0 = std::chrono::steady_clock::now();
  cli::RemoteOutcome out = cli::SimplifyWithRetry(
      s.stub(), RatioSpec(0.5), testing::LoadTestMesh("fandisk.off"), options, &counters);
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(out.status.error_message().find("gave up after 3 attempts"), std::string::npos)
      << out.status.error_message();
  EXPECT_EQ(counters.attempts, 3);
  EXPECT_EQ(counters.resource_exhausted, 3);
  ASSERT_EQ(waits.size(), 2u);
  for (milliseconds w : waits) {
    EXPECT_GE(w.count(), 200);
    EXPECT_LE(w.count(), 240);
  }
  EXPECT_GE(SecondsSince(t0), 0.4);
  EXPECT_NEAR(counters.waited_seconds, (waits[0] + waits[1]).count() / 1e3, 1e-9);
}

// The only queue slot is held, then freed: a later attempt gets in and the result arrives whole.
TEST(Retry, JobGetsInOnceTheQueueHasRoom) {
  server::ServerConfig config = testing::TestConfig();
  config.queue_capacity = 1;
  config.retry_pushback_ms = 150;
  InProcessServer s(config);
  grpc::ClientContext hold_ctx;
  auto hold = s.stub().Simplify(&hold_ctx);
  v1::SimplifyRequest spec_only;
  *spec_only.mutable_spec() = RatioSpec(0.5);
  spec_only.mutable_spec()->set_vertex_count(3);
  spec_only.mutable_spec()->set_face_count(1);
  ASSERT_TRUE(hold->Write(spec_only));
  v1::SimplifyResponse accepted;
  ASSERT_TRUE(hold->Read(&accepted));
  ASSERT_TRUE(accepted.has_accepted());
  std::thread release([&] {
    std::this_thread::sleep_for(milliseconds(400));
    hold_ctx.TryCancel();
  });

  const RawMesh mesh = testing::LoadTestMesh("fandisk.off");
  cli::RetryOptions options;
  options.policy.max_attempts = 20;
  cli::RetryCounters counters;
  cli::RemoteOutcome out =
      cli::SimplifyWithRetry(s.stub(), RatioSpec(0.5), mesh, options, &counters);
  release.join();
  hold->Finish();
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_GE(counters.attempts, 2);
  EXPECT_EQ(counters.resource_exhausted, counters.attempts - 1);
  EXPECT_EQ(out.output.num_vertices(), out.result.output_vertices());
  EXPECT_TRUE(CheckOutput(TopologyOf(mesh), out.output).ok());
}

// Nothing listens yet (a replica starting): UNAVAILABLE attempts, then the server is up and the
// job succeeds on the same channel, soon.
TEST(Retry, ServerThatComesUpLaterGetsTheJob) {
  const int port = testing::FreePort();
  server::ServerConfig config = testing::TestConfig();
  config.listen = absl::StrCat("127.0.0.1:", port);
  cli::RetryOptions options;
  options.channel = cli::MakeChannel(config.listen);
  auto stub = v1::Simplifier::NewStub(options.channel);
  const RawMesh mesh = testing::LoadTestMesh("fandisk.off");
  options.policy.max_attempts = 10;
  options.deadline = std::chrono::system_clock::now() + std::chrono::seconds(60);
  cli::RetryCounters counters;
  cli::RemoteOutcome out;
  std::thread client(
      [&] { out = cli::SimplifyWithRetry(*stub, RatioSpec(0.5), mesh, options, &counters); });
  std::this_thread::sleep_for(milliseconds(700));
  auto up = std::chrono::steady_clock::now();
  InProcessServer s(config);
  client.join();
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_GE(counters.unavailable, 1);
  EXPECT_EQ(counters.attempts, counters.unavailable + 1);
  EXPECT_EQ(out.output.num_faces(), out.result.output_faces());
  // Used within about one backoff once up, not after gRPC's own reconnect backoff.
  EXPECT_LT(SecondsSince(up), 3.0);
}

pid_t SpawnServer(const std::string& address) {
  std::vector<std::string> args = {FEMSIMP_SERVER_BIN, "--listen=" + address,
                                   "--metrics_listen=", "--workers=1", "--threads_per_job=1"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  return pid;
}

// A replica SIGKILLed while it runs the job (no GOAWAY: the channel sees a dead connection) and
// started again on the same port: the job is retried and lands on the new process soon after
// it is up (its Accepted arrives within 8 s; the engine's run after that is not timed, so the
// bound holds on a slow or sanitizer build too). Without the reconnect request between
// attempts every attempt failed at once on the stale connection state for over 8 s.
TEST(Retry, KilledAndRestartedServerGetsTheJobSoon) {
  const std::string address = absl::StrCat("127.0.0.1:", testing::FreePort());
  pid_t pid = SpawnServer(address);
  ASSERT_GT(pid, 0);
  cli::RetryOptions options;
  options.channel = cli::MakeChannel(address);
  auto stub = v1::Simplifier::NewStub(options.channel);
  options.policy.max_attempts = 10;
  options.deadline = std::chrono::system_clock::now() + std::chrono::seconds(60);
  cli::RetryCounters counters;
  cli::RemoteOutcome out;
  std::atomic<bool> running{false};
  std::atomic<int64_t> last_accepted_ns{0};  // steady clock
  options.callbacks.on_accepted = [&](const v1::Accepted&) {
    last_accepted_ns.store(std::chrono::steady_clock::now().time_since_epoch().count());
    running.store(true);
  };
  std::thread client([&] {
    out = cli::SimplifyWithRetry(*stub, RatioSpec(0.01, 1), testing::MakeTorus(600, 600), options,
                                 &counters);
  });
  for (int i = 0; i < 3000 && !running.load(); ++i) std::this_thread::sleep_for(milliseconds(5));
  std::this_thread::sleep_for(milliseconds(100));  // uploading or running
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  std::this_thread::sleep_for(milliseconds(500));
  auto up = std::chrono::steady_clock::now();
  pid = SpawnServer(address);
  ASSERT_GT(pid, 0);
  client.join();
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_GE(counters.unavailable, 1);
  const std::chrono::steady_clock::time_point accepted{
      std::chrono::steady_clock::duration{last_accepted_ns.load()}};
  EXPECT_LT(std::chrono::duration<double>(accepted - up).count(), 8.0)
      << counters.attempts << " attempts";
}

TEST(Retry, UnreachableServerGivesUpAfterMaxAttempts) {
  cli::RetryOptions options;
  options.channel = cli::MakeChannel(absl::StrCat("127.0.0.1:", testing::FreePort()));
  auto stub = v1::Simplifier::NewStub(options.channel);
  options.policy.max_attempts = 3;
  options.policy.initial_backoff = milliseconds(50);
  cli::RetryCounters counters;
  cli::RemoteOutcome out =
      cli::SimplifyWithRetry(*stub, RatioSpec(0.5), testing::MakeTorus(8, 8), options, &counters);
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_NE(out.status.error_message().find("gave up after 3 attempts"), std::string::npos);
  EXPECT_EQ(counters.attempts, 3);
  EXPECT_EQ(counters.unavailable, 3);
}

// Errors another attempt cannot fix are returned at once.
TEST(Retry, LimitsAndBadRequestsAreNotRetried) {
  server::ServerConfig config = testing::TestConfig();
  config.max_vertices = 100;
  InProcessServer s(config);
  cli::RetryOptions options;
  cli::RetryCounters too_big;
  cli::RemoteOutcome out = cli::SimplifyWithRetry(
      s.stub(), RatioSpec(0.5), testing::LoadTestMesh("fandisk.off"), options, &too_big);
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_FALSE(out.retry_pushback_ms.has_value());
  EXPECT_EQ(too_big.attempts, 1);

  cli::RetryCounters bad;
  out = cli::SimplifyWithRetry(s.stub(), RatioSpec(1.5), testing::MakeTorus(6, 6), options, &bad);
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(bad.attempts, 1);
}

// Attempts at 0, 0.5 and 1 s; then the next wait would end past the deadline (1.25 s), which
// the retry loop says at once. A loaded machine (the ASan build beside other work) may make the
// third refusal itself come after the deadline: then the call ends DEADLINE_EXCEEDED, which
// also keeps the bound this test is about (it once failed so, 2026-11-26).
TEST(Retry, DeadlineBoundsAllAttempts) {
  server::ServerConfig config = testing::TestConfig();
  config.queue_capacity = 0;
  config.retry_pushback_ms = 500;
  InProcessServer s(config);
  cli::RetryOptions options;
  options.policy.max_attempts = 100;
  options.deadline = std::chrono::system_clock::now() + milliseconds(1250);
  cli::RetryCounters counters;
  auto t0 = std::chrono::steady_clock::now();
  cli::RemoteOutcome out = cli::SimplifyWithRetry(s.stub(), RatioSpec(0.5),
                                                  testing::MakeTorus(8, 8), options, &counters);
  if (out.status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
    EXPECT_NE(out.status.error_message().find("no time left"), std::string::npos)
        << out.status.error_message();
  } else {
    EXPECT_EQ(out.status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED)
        << out.status.error_message();
  }
  EXPECT_LE(counters.attempts, 3);
  EXPECT_LT(SecondsSince(t0), 1.25 + 0.5);
}

TEST(Retry, CancelEndsTheWaitBetweenAttempts) {
  server::ServerConfig config = testing::TestConfig();
  config.queue_capacity = 0;
  config.retry_pushback_ms = 10000;
  InProcessServer s(config);
  cli::JobCanceller canceller;
  cli::RetryOptions options;
  options.canceller = &canceller;
  std::thread cancel([&] {
    std::this_thread::sleep_for(milliseconds(300));
    canceller.Cancel();
  });
  auto t0 = std::chrono::steady_clock::now();
  cli::RemoteOutcome out =
      cli::SimplifyWithRetry(s.stub(), RatioSpec(0.5), testing::MakeTorus(8, 8), options);
  cancel.join();
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::CANCELLED);
  EXPECT_LT(SecondsSince(t0), 3.0);
}

TEST(Health, ServingForTheServerAndTheSimplifier) {
  InProcessServer s;
  cli::HealthArgs args;
  args.server = s.address();
  cli::HealthOutcome whole = cli::CheckHealth(args);
  EXPECT_TRUE(whole.serving()) << whole.status.error_message() << whole.serving_status;
  args.service = "femsimp.v1.Simplifier";
  EXPECT_TRUE(cli::CheckHealth(args).serving());
  args.service = "no.such.Service";
  EXPECT_EQ(cli::CheckHealth(args).status.error_code(), grpc::StatusCode::NOT_FOUND);
}

// From shutdown on (SIGTERM), health says NOT_SERVING while a running job drains.
TEST(Health, NotServingWhileShuttingDown) {
  server::ServerConfig config = testing::TestConfig();
  config.grace_period_seconds = 30;
  InProcessServer s(config);
  cli::HealthArgs args;
  args.server = s.address();
  grpc::ClientContext ctx;
  std::string job_id;
  std::atomic<bool> accepted{false};
  cli::RemoteCallbacks cb;
  cb.on_progress = [&](const v1::Progress&) { accepted.store(true); };
  cli::RemoteOutcome out;
  std::thread job([&] {
    out = cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.01, 1), testing::MakeTorus(700, 700), cb,
                              false);
  });
  // The first pass's progress: the job runs (60 s at most: the torus takes a few seconds to
  // build and simplify a pass on a sanitizer build).
  for (int i = 0; i < 6000 && !accepted.load(); ++i) std::this_thread::sleep_for(milliseconds(10));
  if (!accepted.load()) {
    ctx.TryCancel();
    job.join();
    FAIL() << "the job made no progress in 60 s: " << out.status.error_message();
  }
  std::thread stopper([&] { s.server().Shutdown(); });
  std::string seen;
  for (int i = 0; i < 200; ++i) {
    cli::HealthOutcome h = cli::CheckHealth(args);
    if (h.status.ok() && h.serving_status == "NOT_SERVING") {
      seen = h.serving_status;
      break;
    }
    std::this_thread::sleep_for(milliseconds(10));
  }
  stopper.join();
  job.join();
  EXPECT_EQ(seen, "NOT_SERVING");
  EXPECT_TRUE(out.status.ok()) << out.status.error_message();  // drained within the grace period
}

// A target with several addresses gets its calls spread over all of them (round_robin in
// MakeChannel), and connections closed by --max_connection_age_seconds neither fail a running
// job nor stop later ones. A call that meets a connection as it ages out may end UNAVAILABLE
// after its server ran the job (a known gRPC race around GOAWAY; seen once in 20 calls under
// AddressSanitizer): the client's retry runs it again, so the servers may count more jobs
// than calls, never more than the attempts.
TEST(Balancing, CallsSpreadOverEveryAddressAcrossConnectionAging) {
  server::ServerConfig config = testing::TestConfig();
  config.max_connection_age_seconds = 0.3;
  InProcessServer a(config), b(config);
  auto stub = v1::Simplifier::NewStub(
      cli::MakeChannel(absl::StrCat("ipv4:", a.address(), ",", b.address())));
  const RawMesh mesh = testing::LoadTestMesh("femur.off");
  int attempts = 0;
  for (int i = 0; i < 20; ++i) {
    cli::RetryCounters counters;
    cli::RemoteOutcome out =
        cli::SimplifyWithRetry(*stub, RatioSpec(0.5), mesh, cli::RetryOptions{}, &counters);
    ASSERT_TRUE(out.status.ok()) << out.status.error_message();
    attempts += counters.attempts;
    if (i % 5 == 4) std::this_thread::sleep_for(milliseconds(150));  // let connections age out
  }
  const std::string ok = "femsimp_jobs_total{status=\"OK\"}";
  double on_a = testing::ParseMetrics(testing::HttpGet(a.server().metrics_port(), "/metrics"))[ok];
  double on_b = testing::ParseMetrics(testing::HttpGet(b.server().metrics_port(), "/metrics"))[ok];
  EXPECT_GE(on_a + on_b, 20);
  EXPECT_LE(on_a + on_b, attempts) << "a server ran a job no attempt asked for";
  std::printf("20 calls, %d attempts, %g jobs run\n", attempts, on_a + on_b);
  EXPECT_GE(on_a, 5);
  EXPECT_GE(on_b, 5);
}

TEST(HealthArgs, ParsesAndRejects) {
  absl::StatusOr<cli::HealthArgs> h =
      cli::ParseHealthArgs({"--server", "127.0.0.1:5", "--service=x.Y", "--timeout", "2.5"});
  ASSERT_TRUE(h.ok()) << h.status();
  EXPECT_EQ(h->server, "127.0.0.1:5");
  EXPECT_EQ(h->service, "x.Y");
  EXPECT_EQ(h->timeout_seconds, 2.5);
  EXPECT_FALSE(cli::ParseHealthArgs({}).ok());
  EXPECT_FALSE(cli::ParseHealthArgs({"--server", "nohostport"}).ok());
  EXPECT_FALSE(cli::ParseHealthArgs({"--server", "a:1", "--timeout", "0"}).ok());
  EXPECT_FALSE(cli::ParseHealthArgs({"--server", "a:1", "--bogus"}).ok());
  EXPECT_FALSE(cli::ParseHealthArgs({"--server"}).ok());
}

}  // namespace
}  // namespace femsimp
