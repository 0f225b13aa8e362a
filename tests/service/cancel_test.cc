// Cancellation inside a pass, through the server: a passed deadline, CancelJob and a client-side
// cancel end a running job within 0.5 s on both back ends, and the worker is free afterwards.
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "gtest/gtest.h"
#include "tests/service/test_util.h"
#include "tests/support/sanitizers.h"

namespace femsimp {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using testing::ExpectWorkerFree;
using testing::GetJob;
using testing::InProcessServer;
using testing::WaitWhile;

// What the issue demands between the deadline or the cancel and the end of the job.
// The release build's bound. The AddressSanitizer build (FEMSIMP_ASAN) runs the engine between
// two cancellation checks several times slower: there the bound is 3 s (0.6 to 1.43 s were
// measured on a loaded 2-core machine); what that build checks is the cancel path's memory, not
// its speed.
constexpr double kMaxLatencySeconds = testing::kUnderAddressSanitizer ? 3.0 : 0.5;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// 1M vertices, 2M faces; made, uploaded and built in 2.5 to 3.6 s here (more when loaded). With
// the options below the set-up takes about a second and the first pass several (more on a
// loaded machine): the tests cancel once the
// job's JobInfo says the first pass's removals have begun (engine/cancel latency on its own,
// wherever it lands: bench/cancel_latency). Under a sanitizer, a quarter of that: the engine
// runs 3 to 5 times slower there, so its first pass still takes seconds, and the set-up's
// 20 to 30 s per test are spared (these tests run one at a time).
const RawMesh& BigMesh() {
  static const RawMesh mesh =
      testing::kUnderSanitizer ? testing::MakeTorus(500, 500) : testing::MakeTorus(1000, 1000);
  return mesh;
}

v1::JobSpec LongJob(v1::Backend backend) {
  v1::JobSpec spec;
  spec.set_client_label("long");
  spec.mutable_options()->set_target_vertices(50);
  spec.mutable_options()->set_threads(1);
  spec.mutable_options()->set_backend(backend);
  if (backend == v1::BACKEND_CELL) {
    spec.mutable_options()->mutable_cell()->set_spes(1);
  } else {
    // Bounds that make each collapse dearer (deviation and volume checks), not the cost phase.
    spec.mutable_options()->set_tolerance_relative(0.01);
    spec.mutable_options()->set_max_volume_change(0.01);
  }
  return spec;
}

// A long job on its own thread: the test cancels it while it runs.
class LongCall {
 public:
  LongCall(InProcessServer& s, v1::Backend backend,
           std::optional<std::chrono::system_clock::time_point> deadline = std::nullopt)
      : s_(s) {
    if (deadline) ctx_.set_deadline(*deadline);
    cli::RemoteCallbacks cb;
    cb.on_accepted = [this](const v1::Accepted& a) {
      std::lock_guard<std::mutex> lock(mu_);
      id_ = a.job_id();
      cv_.notify_all();
    };
    thread_ = std::thread([this, backend, cb] {
      outcome_ = cli::RemoteSimplify(s_.stub(), ctx_, LongJob(backend), BigMesh(), cb, false);
      ended_ = Clock::now();
    });
  }
  ~LongCall() { Join(); }

  // Waits for the job's id, then until it runs; false when it never did.
  bool WaitRunning() {
    std::string id;
    {
      std::unique_lock<std::mutex> lock(mu_);
      if (!cv_.wait_for(lock, std::chrono::seconds(60), [&] { return !id_.empty(); })) return false;
      id = id_;
    }
    std::optional<v1::JobInfo> info = WaitWhile(s_.stub(), id, v1::JOB_STATE_QUEUED);
    running_since_ = Clock::now();
    return info && info->state() == v1::JOB_STATE_RUNNING;
  }
  void Join() {
    if (thread_.joinable()) thread_.join();
  }

  grpc::ClientContext& ctx() { return ctx_; }
  std::string id() {
    std::lock_guard<std::mutex> lock(mu_);
    return id_;
  }
  Clock::time_point running_since() const { return running_since_; }
  // After Join():
  const cli::RemoteOutcome& outcome() const { return outcome_; }
  Clock::time_point ended() const { return ended_; }

 private:
  InProcessServer& s_;
  grpc::ClientContext ctx_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::string id_;
  Clock::time_point running_since_{}, ended_{};
  cli::RemoteOutcome outcome_;
  std::thread thread_;
};

std::string BackendName(const ::testing::TestParamInfo<v1::Backend>& p) {
  return p.param == v1::BACKEND_CELL ? "Cell" : "Native";
}

class CancelInPass : public ::testing::TestWithParam<v1::Backend> {
 protected:
  // Waits until the first pass's removals have begun (JobInfo.passes_started), then a tenth
  // of a second more: inside the pass, past its cost and sort.
  static void IntoAPass(InProcessServer& s, LongCall& call) {
    ASSERT_TRUE(call.WaitRunning()) << "the job never ran";
    const Clock::time_point give_up = Clock::now() + std::chrono::seconds(60);
    std::optional<v1::JobInfo> info;
    for (;;) {
      info = GetJob(s.stub(), call.id());
      ASSERT_TRUE(info);
      ASSERT_EQ(info->state(), v1::JOB_STATE_RUNNING);
      if (info->passes_started() >= 1) break;
      ASSERT_LT(Clock::now(), give_up) << "the first pass never began";
      std::this_thread::sleep_for(milliseconds(5));
    }
    EXPECT_EQ(info->passes_done(), 0u);  // the first pass takes seconds
    std::this_thread::sleep_for(milliseconds(100));
  }
};

TEST_P(CancelInPass, CancelJobEndsTheCallWithinHalfASecond) {
  InProcessServer s(testing::OneWorkerConfig());
  LongCall call(s, GetParam());
  ASSERT_NO_FATAL_FAILURE(IntoAPass(s, call));

  const Clock::time_point cancelled = Clock::now();
  grpc::ClientContext c;
  v1::CancelJobRequest req;
  req.set_job_id(call.id());
  v1::CancelJobResponse resp;
  ASSERT_TRUE(s.stub().CancelJob(&c, req, &resp).ok());
  EXPECT_EQ(resp.previous_state(), v1::JOB_STATE_RUNNING);
  call.Join();
  const double latency = std::chrono::duration<double>(call.ended() - cancelled).count();
  std::printf("CancelJob (%s) in a pass: the call ended %.3f s after the cancel\n",
              GetParam() == v1::BACKEND_CELL ? "cell" : "native", latency);

  EXPECT_EQ(call.outcome().status.error_code(), grpc::StatusCode::CANCELLED)
      << call.outcome().status.error_message();
  EXPECT_NE(call.outcome().status.error_message().find("CancelJob"), std::string::npos);
  EXPECT_LT(latency, kMaxLatencySeconds);
  std::optional<v1::JobInfo> after = GetJob(s.stub(), call.id());
  ASSERT_TRUE(after);
  EXPECT_EQ(after->state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(after->status_code(), "CANCELLED");
  EXPECT_GE(after->passes_done(), 1u);  // the cancelled pass is reported too
  ExpectWorkerFree(s);
}

TEST_P(CancelInPass, ClientCancelEndsTheJobWithinHalfASecond) {
  InProcessServer s(testing::OneWorkerConfig());
  LongCall call(s, GetParam());
  ASSERT_NO_FATAL_FAILURE(IntoAPass(s, call));

  const Clock::time_point cancelled = Clock::now();
  call.ctx().TryCancel();
  std::optional<v1::JobInfo> after = WaitWhile(s.stub(), call.id(), v1::JOB_STATE_RUNNING);
  const double latency = Since(cancelled);
  call.Join();
  std::printf("client cancel (%s) in a pass: the job ended %.3f s after the cancel\n",
              GetParam() == v1::BACKEND_CELL ? "cell" : "native", latency);

  EXPECT_EQ(call.outcome().status.error_code(), grpc::StatusCode::CANCELLED);
  ASSERT_TRUE(after);
  EXPECT_EQ(after->state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(after->status_code(), "CANCELLED") << after->status_message();
  EXPECT_GE(after->passes_done(), 1u);  // the cancelled pass is reported too
  EXPECT_LT(latency, kMaxLatencySeconds);
  ExpectWorkerFree(s);
}

TEST_P(CancelInPass, DeadlineEndsTheJobWithinHalfASecond) {
  InProcessServer s(testing::OneWorkerConfig());
  // The deadline must fall after the upload and the mesh build: about half a second alone, but
  // several times that on a loaded machine (3.5 s once in CI, beside the CAD set's runs; a
  // fixed 3.5 s deadline then fell before the job ran). So a first call measures them here and
  // now, and is cancelled once its job runs; the deadline leaves twice that and 1.5 s more, and
  // falls into the set-up (about a second) or a pass (each takes seconds).
  double to_running = 0;
  {
    const Clock::time_point start = Clock::now();
    LongCall probe(s, GetParam());
    ASSERT_TRUE(probe.WaitRunning()) << "the first job never ran";
    to_running = std::chrono::duration<double>(probe.running_since() - start).count();
    probe.ctx().TryCancel();
    WaitWhile(s.stub(), probe.id(), v1::JOB_STATE_RUNNING);  // the worker is free again
  }
  const milliseconds margin(static_cast<int64_t>(1000 * (2 * to_running + 1.5)));
  const auto deadline = std::chrono::system_clock::now() + margin;
  const Clock::time_point steady_deadline = Clock::now() + margin;
  LongCall call(s, GetParam(), deadline);
  ASSERT_TRUE(call.WaitRunning()) << "the job never ran";
  ASSERT_LT(call.running_since(), steady_deadline) << "the upload took the whole deadline";
  std::optional<v1::JobInfo> after = WaitWhile(s.stub(), call.id(), v1::JOB_STATE_RUNNING);
  const double latency = Since(steady_deadline);
  call.Join();
  const double call_latency = std::chrono::duration<double>(call.ended() - steady_deadline).count();
  ASSERT_TRUE(after);
  std::printf(
      "deadline (%s; the first call ran after %.3f s), %.3f s into the job, in pass %u: the "
      "call ended %.3f s and the job %.3f s after it\n",
      GetParam() == v1::BACKEND_CELL ? "cell" : "native", to_running,
      std::chrono::duration<double>(steady_deadline - call.running_since()).count(),
      after->passes_done(), call_latency, latency);

  EXPECT_EQ(call.outcome().status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED)
      << call.outcome().status.error_message();
  EXPECT_LT(call_latency, kMaxLatencySeconds);
  EXPECT_EQ(after->state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(after->status_code(), "DEADLINE_EXCEEDED") << after->status_message();
  // The pass the deadline cut, if any, is reported too.
  EXPECT_EQ(after->passes_done(), after->passes_started());
  EXPECT_LT(latency, kMaxLatencySeconds);
  ExpectWorkerFree(s);
}

INSTANTIATE_TEST_SUITE_P(Backends, CancelInPass,
                         ::testing::Values(v1::BACKEND_NATIVE, v1::BACKEND_CELL), BackendName);

}  // namespace
}  // namespace femsimp
