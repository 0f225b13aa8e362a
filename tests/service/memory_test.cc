// Every admitted job ends, also when memory runs out (issue 15, item 1): an allocation that
// fails while the mesh is received and prepared, or while the engine runs, fails that job with
// RESOURCE_EXHAUSTED and a message that says so, frees its queue slot, and the server goes on.
// This binary replaces operator new: once armed, any allocation above the limit throws
// std::bad_alloc (the nothrow forms return null), as a real shortage would (the mesh's arrays
// are by far the largest).
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <new>
#include <optional>
#include <string>
#include <thread>

#include "gtest/gtest.h"
#include "tests/service/test_util.h"

namespace {
std::atomic<size_t> g_fail_above{0};  // 0: never fail
}  // namespace

// GCC 12 with -fsanitize=address (FEMSIMP_ASAN) inlines these into gtest's `new TestClass` and
// takes the free() for a mismatch with operator new: both sides are replaced here, malloc and free.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(size_t size) {
  const size_t limit = g_fail_above.load(std::memory_order_relaxed);
  if (limit != 0 && size > limit) throw std::bad_alloc();
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }
// The nothrow forms too (gRPC uses them): left to the runtime's, they allocated with its own
// operator new while the replaced delete above freed with free(), a mismatch AddressSanitizer
// reported (alloc-dealloc-mismatch in grpc_core::ChannelInit::Builder::Build).
void* operator new(size_t size, const std::nothrow_t&) noexcept {
  try {
    return operator new(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](size_t size, const std::nothrow_t&) noexcept {
  try {
    return operator new(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace femsimp {
namespace {

using testing::GetJob;
using testing::InProcessServer;

constexpr size_t kMiB = size_t{1} << 20;

// 1M vertices, 2M faces: built, its half-edges alone take 96 MiB, and the engine's face index
// and sort arrays several MiB more.
const RawMesh& BigMesh() {
  static const RawMesh mesh = testing::MakeTorus(1000, 1000);
  return mesh;
}

TEST(OutOfMemory, WhilePreparingTheMeshFailsTheJobAndFreesItsSlot) {
  server::ServerConfig config = testing::OneWorkerConfig();
  config.queue_capacity = 1;  // a slot held for good would refuse every later job
  InProcessServer s(config);
  const RawMesh& mesh = BigMesh();
  v1::JobSpec spec = testing::RatioSpec(0.5, 1);
  // The upload's arrays (24 MiB at most) and the repair's tables (under 80 MiB) fit; the
  // half-edges (96 MiB, a std::vector) do not. (Abseil's hash tables are not exception-safe:
  // a failure inside one is not survivable, which is why a shortage is injected here.)
  g_fail_above = 90 * kMiB;
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, mesh);
  g_fail_above = 0;
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
      << out.status.error_message();
  EXPECT_NE(out.status.error_message().find("not enough memory"), std::string::npos)
      << out.status.error_message();
  EXPECT_NE(out.status.error_message().find("1000000 vertices"), std::string::npos)
      << out.status.error_message();
  testing::ExpectWorkerFree(s);
}

TEST(OutOfMemory, WhileTheEngineRunsFailsTheJobAndFreesTheWorker) {
  InProcessServer s(testing::OneWorkerConfig());
  std::atomic<bool> stop_watch{false};
  std::string job_id;
  cli::RemoteCallbacks cb;
  std::atomic<bool> accepted{false};
  cb.on_accepted = [&](const v1::Accepted& a) {
    job_id = a.job_id();
    accepted = true;
  };
  // Once the job runs (the mesh is built), the engine's next allocation above 4 MiB fails:
  // there is always one (the face index, the pass's sorted costs: 8 MiB and more).
  std::thread arm([&] {
    while (!stop_watch && !accepted) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    while (!stop_watch) {
      std::optional<v1::JobInfo> info = GetJob(s.stub(), job_id);
      if (info && info->state() == v1::JOB_STATE_RUNNING) {
        g_fail_above = 4 * kMiB;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
  v1::JobSpec spec = testing::RatioSpec(0.5, 1);
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, BigMesh(), cb, false);
  stop_watch = true;
  arm.join();
  g_fail_above = 0;
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
      << out.status.error_message();
  EXPECT_NE(out.status.error_message().find("not enough memory to simplify the mesh"),
            std::string::npos)
      << out.status.error_message();
  std::optional<v1::JobInfo> info = GetJob(s.stub(), job_id);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(info->status_code(), "RESOURCE_EXHAUSTED");
  testing::ExpectWorkerFree(s);
}

}  // namespace
}  // namespace femsimp
