#include "cellsim/local_store.h"

#include <cstdint>

#include "cellsim/spe_context.h"
#include "gtest/gtest.h"
#include "tests/support/cellsim.h"

namespace femsimp::cellsim {
namespace {

using testing::MakeSpe;

TEST(LocalStoreTest, AllocatesAlignedWithinBudgetAndReportsOverflow) {
  absl::StatusOr<std::unique_ptr<LocalStore>> ls = LocalStore::Create(4096);
  ASSERT_TRUE(ls.ok()) << ls.status();
  absl::StatusOr<std::byte*> a = (*ls)->Allocate(100, 16, "a");
  ASSERT_TRUE(a.ok());
  absl::StatusOr<std::byte*> b = (*ls)->Allocate(1000, 128, "b");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(reinterpret_cast<uintptr_t>(*b) % 128, 0u);
  EXPECT_TRUE((*ls)->Contains(*b, 1000));
  EXPECT_EQ((*ls)->used(), 128u + 1000u);

  absl::StatusOr<std::byte*> c = (*ls)->Allocate(4000, 16, "too big");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(c.status().message().find("4000 bytes for 'too big'"), std::string::npos) << c.status();
  EXPECT_NE(c.status().message().find("2968 of 4096 bytes left"), std::string::npos) << c.status();

  const LocalStore::Marker m = (*ls)->Mark();
  ASSERT_TRUE((*ls)->Allocate(2000).ok());
  (*ls)->Release(m);
  EXPECT_EQ((*ls)->used(), m);
  EXPECT_FALSE((*ls)->Allocate(16, 24).ok());  // Not a power of two.
  EXPECT_FALSE(LocalStore::Create(100).ok());  // Not a multiple of 16.
}

TEST(LocalStoreTest, CacheLargerThanLocalStoreFails) {
  MainMemory memory;
  SpeConfig config;
  config.cache.size_bytes = 256 * 1024;  // Lines alone fill the store; tags cannot fit.
  absl::StatusOr<std::unique_ptr<SpeContext>> spe = SpeContext::Create(3, 4, config, &memory);
  ASSERT_FALSE(spe.ok());
  EXPECT_EQ(spe.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(spe.status().message().find("SPE 3"), std::string::npos) << spe.status();
  EXPECT_NE(spe.status().message().find("cache tags"), std::string::npos) << spe.status();

  config.cache.size_bytes = 128 * 1024;
  spe = SpeContext::Create(0, 1, config, &memory);
  ASSERT_TRUE(spe.ok()) << spe.status();
  EXPECT_EQ((*spe)->local_store().used(), 128u * 1024 + (*spe)->cache().tag_bytes());
}

TEST(LocalStoreTest, BadCacheGeometryIsRejected) {
  MainMemory memory;
  SpeConfig config;
  config.cache.line_bytes = 96;
  EXPECT_EQ(SpeContext::Create(0, 1, config, &memory).status().code(),
            absl::StatusCode::kInvalidArgument);
  config.cache.line_bytes = 128;
  config.cache.size_bytes = 3 * 128 * 4;  // Three sets: not a power of two.
  EXPECT_EQ(SpeContext::Create(0, 1, config, &memory).status().code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(LocalStoreTest, SoftwareThreadStacksCountAgainstTheBudget) {
  MainMemory memory;
  SpeConfig config;
  config.cache.size_bytes = 64 * 1024;
  config.thread_stack_bytes = 64 * 1024;
  auto spe = MakeSpe(memory, config);
  ASSERT_NE(spe, nullptr);
  const size_t used_before = spe->local_store().used();

  int ran = 0;
  // Cache 64 KiB + tags + 3 x 64 KiB stacks + control blocks > 256 KiB.
  absl::Status s = spe->RunThreads(3, [&](SpeContext&, int) { ++ran; });
  EXPECT_EQ(s.code(), absl::StatusCode::kResourceExhausted) << s;
  EXPECT_NE(s.message().find("stack"), std::string::npos) << s;
  EXPECT_EQ(ran, 0);
  EXPECT_EQ(spe->local_store().used(), used_before);

  size_t used_inside = 0;
  s = spe->RunThreads(2, [&](SpeContext& ctx, int) {
    ++ran;
    used_inside = ctx.local_store().used();
  });
  EXPECT_TRUE(s.ok()) << s;
  EXPECT_EQ(ran, 2);
  EXPECT_GE(used_inside, used_before + 2 * 64 * 1024);
  EXPECT_EQ(spe->local_store().used(), used_before);  // Stacks released afterwards.
}

}  // namespace
}  // namespace femsimp::cellsim
