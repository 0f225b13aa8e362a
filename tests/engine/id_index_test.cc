// IdIndex (engine/id_index.h): keys derived from the ids it holds, found again after the table
// grows far past its first size; Exchange keeps a chain of the ids a key had.
#include "engine/id_index.h"

#include <cstdint>
#include <vector>

#include "gtest/gtest.h"

namespace femsimp {
namespace {

TEST(IdIndex, FindsEveryKeyAfterGrowing) {
  std::vector<int64_t> keys;  // id -> key
  const auto key_of = [&](uint32_t id) { return keys[id]; };
  IdIndex<int64_t, decltype(key_of)> index(1, key_of);
  for (uint32_t id = 0; id < 20000; ++id) {
    keys.push_back(int64_t(id) * 7919 - 50000);
    EXPECT_EQ(index.FindOrInsert(keys.back(), id), id);
  }
  for (uint32_t id = 0; id < 20000; ++id) {
    EXPECT_EQ(index.Find(keys[id]), id);
    EXPECT_EQ(index.FindOrInsert(keys[id], 99999), id);  // present: the old id, nothing stored
  }
  EXPECT_EQ(index.Find(3), (IdIndex<int64_t, decltype(key_of)>::kNoId));
}

TEST(IdIndex, ExchangeReturnsThePreviousId) {
  std::vector<int> cell = {5, 5, 8, 5};  // id -> key
  const auto key_of = [&](uint32_t id) { return cell[id]; };
  IdIndex<int, decltype(key_of)> index(2, key_of);
  constexpr uint32_t kNo = IdIndex<int, decltype(key_of)>::kNoId;
  EXPECT_EQ(index.Exchange(5, 0), kNo);
  EXPECT_EQ(index.Exchange(5, 1), 0u);
  EXPECT_EQ(index.Exchange(8, 2), kNo);
  EXPECT_EQ(index.Exchange(5, 3), 1u);
  EXPECT_EQ(index.Find(5), 3u);
  EXPECT_EQ(index.Find(8), 2u);
  EXPECT_EQ(index.Find(6), kNo);
}

}  // namespace
}  // namespace femsimp
