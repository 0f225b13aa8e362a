#include "cellsim/atomic_unit.h"

#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include "cellsim/runtime.h"
#include "gtest/gtest.h"
#include "tests/support/cellsim.h"

namespace femsimp::cellsim {
namespace {

using testing::MakeSpe;
using testing::Quad;
using testing::QuadArray;

TEST(AtomicUnitTest, ReservationIsLostWhenAnotherSpeWrites) {
  std::vector<uint32_t> words(8, 0);
  MainMemory memory;
  ASSERT_TRUE(memory.Register(words.data(), words.size() * 4, "status").ok());
  auto a = MakeSpe(memory, {}, 0, 2);
  auto b = MakeSpe(memory, {}, 1, 2);

  absl::StatusOr<uint32_t> v = a->atomic().GetLlar(&words[1]);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(*v, 0u);
  EXPECT_TRUE(*a->atomic().PutLlc(&words[1], 1));
  EXPECT_FALSE(*a->atomic().PutLlc(&words[1], 2));  // Reservation used up.
  EXPECT_EQ(words[1], 1u);

  ASSERT_TRUE(a->atomic().GetLlar(&words[1]).ok());
  ASSERT_TRUE(b->atomic().PutLluc(&words[1], 7).ok());  // Another SPE writes in between.
  EXPECT_FALSE(*a->atomic().PutLlc(&words[1], 2));
  EXPECT_EQ(words[1], 7u);

  uint32_t expected = 0;
  EXPECT_FALSE(*a->atomic().CompareAndSwap(&words[1], expected, 9));
  EXPECT_EQ(expected, 7u);  // Reports what it saw.
  EXPECT_TRUE(*a->atomic().CompareAndSwap(&words[1], expected, 9));
  EXPECT_EQ(*b->atomic().Load(&words[1]), 9u);

  const SpeCounters& c = a->counters();
  EXPECT_EQ(c.atomic_getllar, 4u);
  EXPECT_EQ(c.atomic_putllc_success, 2u);
  EXPECT_EQ(c.atomic_putllc_failure, 2u);
  const CostModel& cost = a->config().cost;
  EXPECT_EQ(c.atomic_cycles, 4 * cost.atomic_getllar_cycles + 4 * cost.atomic_putllc_cycles);
  EXPECT_EQ(b->counters().AtomicOps(), 2u);
}

TEST(AtomicUnitTest, RejectsMisalignedAndUnregisteredWords) {
  alignas(16) uint32_t words[4] = {};
  MainMemory memory;
  ASSERT_TRUE(memory.Register(words, sizeof(words), "status").ok());
  auto spe = MakeSpe(memory);
  auto* misaligned = reinterpret_cast<uint32_t*>(reinterpret_cast<char*>(words) + 2);
  EXPECT_EQ(spe->atomic().GetLlar(misaligned).status().code(), absl::StatusCode::kInvalidArgument);
  uint32_t outside = 0;
  EXPECT_EQ(spe->atomic().Load(&outside).status().code(), absl::StatusCode::kOutOfRange);
  EXPECT_EQ(spe->counters().AtomicOps(), 0u);
}

// 16 SPEs on 16 host threads increment shared counters with reservation loops, and move a
// DMA-written quadword under a CAS lock: no update may be lost, and data put before the release
// must be seen by the next SPE that acquires the lock.
TEST(AtomicUnitTest, NoLostUpdatesUnderContention) {
  constexpr int kSpes = 16;
  constexpr int kIncrements = 300;
  alignas(16) uint32_t words[4] = {};  // [0]: counter, [1]: lock.
  QuadArray shared(1);
  shared[0] = Quad{{0, 0, 0, 0}};
  RuntimeConfig config;
  config.num_spes = kSpes;
  config.spe.cache.size_bytes = 16 * 1024;
  config.spe.local_store_bytes = 64 * 1024;
  absl::StatusOr<std::unique_ptr<Runtime>> rt = Runtime::Create(config);
  ASSERT_TRUE(rt.ok()) << rt.status();
  ASSERT_TRUE((*rt)->RegisterMainMemory(words, sizeof(words), "words").ok());
  ASSERT_TRUE((*rt)->RegisterMainMemory(shared.data(), shared.bytes(), "shared").ok());

  absl::Status s = (*rt)->Run([&](SpeContext& spe) {
    AtomicUnit& atomic = spe.atomic();
    absl::StatusOr<std::byte*> buf = spe.local_store().Allocate(16);
    if (!buf.ok()) return spe.ReportError(buf.status());
    const uint64_t ea = Ea(&shared[0]);
    for (int i = 0; i < kIncrements; ++i) {
      // Counter: getllar / putllc loop.
      for (;;) {
        absl::StatusOr<uint32_t> v = atomic.GetLlar(&words[0]);
        if (!v.ok()) return spe.ReportError(v.status());
        if (*atomic.PutLlc(&words[0], *v + 1)) break;
      }
      // Lock, read-modify-write the quadword by DMA, release.
      for (;;) {
        uint32_t expected = 0;
        if (*atomic.CompareAndSwap(&words[1], expected, 1)) break;
        ++spe.counters().lock_conflicts;
        std::this_thread::yield();  // The holder may be descheduled on a busy host.
      }
      spe.cache().Dirty(ea);  // The line may be stale: another SPE wrote it.
      absl::StatusOr<Quad> q = spe.cache().ReadValue<Quad>(ea);
      if (!q.ok()) return spe.ReportError(q.status());
      q->w[0] += 1;
      q->w[spe.index() % 3 + 1] += 1;
      std::memcpy(*buf, &*q, 16);
      if (absl::Status p = spe.dma().Put(*buf, ea, 16, 0).status(); !p.ok()) {
        return spe.ReportError(p);
      }
      (void)spe.dma().WaitTagMask(1);
      if (absl::Status r = atomic.PutLluc(&words[1], 0); !r.ok()) return spe.ReportError(r);
    }
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(words[0], static_cast<uint32_t>(kSpes * kIncrements));
  EXPECT_EQ(shared[0].w[0], static_cast<uint32_t>(kSpes * kIncrements));
  EXPECT_EQ(shared[0].w[1] + shared[0].w[2] + shared[0].w[3],
            static_cast<uint32_t>(kSpes * kIncrements));
  const SpeCounters total = (*rt)->TotalCounters();
  EXPECT_EQ(total.atomic_putllc_success, 2u * kSpes * kIncrements);
  EXPECT_EQ(total.atomic_putlluc, 1u * kSpes * kIncrements);
}

}  // namespace
}  // namespace femsimp::cellsim
