// engine/huge_page_allocator.h: large arrays start on a 2 MiB boundary (where a huge page can
// back them), small ones come from the heap, and the arrays construct and destroy their elements.
#include "engine/huge_page_allocator.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>

namespace femsimp {
namespace {

uintptr_t Address(const void* p) { return reinterpret_cast<uintptr_t>(p); }

TEST(HugePageAllocator, LargeArraysStartOnAHugePage) {
  HugePageVector<uint64_t> large(kHugePageBytes / sizeof(uint64_t) + 1, 7);
  EXPECT_EQ(Address(large.data()) % kHugePageBytes, 0u);
  EXPECT_EQ(large.back(), 7u);
  // Growing moves it to another large array, the values with it.
  large.resize(2 * large.size(), 9);
  EXPECT_EQ(Address(large.data()) % kHugePageBytes, 0u);
  EXPECT_EQ(large.front(), 7u);
  EXPECT_EQ(large.back(), 9u);
  // Small arrays come from the heap as usual (and need no such alignment).
  HugePageVector<uint64_t> small(16, 3);
  EXPECT_EQ(small[15], 3u);
}

TEST(HugePageAllocator, ArraysOfAtomicsStartAtZero) {
  const size_t n = kHugePageBytes / sizeof(std::atomic<uint32_t>) + 5;
  HugePageArray<std::atomic<uint32_t>> status = MakeHugePageArray<std::atomic<uint32_t>>(n);
  EXPECT_EQ(Address(status.get()) % kHugePageBytes, 0u);
  uint64_t sum = 0;
  for (size_t i = 0; i < n; ++i) sum += status[i].load();
  EXPECT_EQ(sum, 0u);
  status[n - 1].store(5);
  EXPECT_EQ(status[n - 1].load(), 5u);
}

struct Counted {
  static inline int live = 0;
  Counted() { ++live; }
  ~Counted() { --live; }
  char pad[64];
};

TEST(HugePageAllocator, ArraysDestroyTheirElements) {
  for (const size_t n : {size_t{10}, kHugePageBytes / sizeof(Counted) + 1}) {
    {
      HugePageArray<Counted> a = MakeHugePageArrayForOverwrite<Counted>(n);
      EXPECT_EQ(Counted::live, static_cast<int>(n));
    }
    EXPECT_EQ(Counted::live, 0) << n;
  }
}

}  // namespace
}  // namespace femsimp
