// ContainingBoxes (engine/box_containment.h): the same answer as testing every pair, on boxes
// nested, disjoint, touching, flat and all in one plane.
#include "engine/box_containment.h"

#include <random>
#include <vector>

#include "gtest/gtest.h"

namespace femsimp {
namespace {

std::vector<std::vector<uint32_t>> EveryPair(const std::vector<AxisBox>& boxes) {
  std::vector<std::vector<uint32_t>> out(boxes.size());
  for (uint32_t i = 0; i < boxes.size(); ++i)
    for (uint32_t j = 0; j < boxes.size(); ++j) {
      bool inside = i != j;
      for (int k = 0; k < 3; ++k)
        inside = inside && boxes[i].lo[k] >= boxes[j].lo[k] && boxes[i].hi[k] <= boxes[j].hi[k];
      if (inside) out[i].push_back(j);
    }
  return out;
}

TEST(BoxContainment, SameAsEveryPair) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(0, 100), size(0, 3);
  std::vector<AxisBox> boxes;
  for (int i = 0; i < 2000; ++i) {  // small parts scattered
    AxisBox b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = at(rng);
      b.hi[k] = b.lo[k] + size(rng);
    }
    boxes.push_back(b);
  }
  for (int i = 0; i < 10; ++i)  // nested shells around the middle, one the whole box
    boxes.push_back(
        {{40.0 - 4 * i, 40.0 - 4 * i, 40.0 - 4 * i}, {60.0 + 4 * i, 60.0 + 4 * i, 60.0 + 4 * i}});
  boxes.push_back({{0, 0, 0}, {103, 103, 103}});
  boxes.push_back(boxes.front());           // a copy: each contains the other
  boxes.push_back({{5, 5, 5}, {5, 5, 5}});  // a point
  const std::vector<std::vector<uint32_t>> got = ContainingBoxes(boxes);
  EXPECT_EQ(got, EveryPair(boxes));
  EXPECT_GE(got[2000].size(), 10u);  // the innermost shell is in the nine others and the whole
}

TEST(BoxContainment, FlatAndFewBoxes) {
  std::vector<AxisBox> flat = {
      {{0, 0, 0}, {10, 10, 0}}, {{1, 1, 0}, {2, 2, 0}}, {{5, 5, 0}, {12, 6, 0}}};
  EXPECT_EQ(ContainingBoxes(flat), EveryPair(flat));
  EXPECT_EQ(ContainingBoxes(flat)[1], std::vector<uint32_t>{0});
  EXPECT_EQ(ContainingBoxes({}).size(), 0u);
  EXPECT_EQ(ContainingBoxes({flat[0]}), std::vector<std::vector<uint32_t>>(1));
}

}  // namespace
}  // namespace femsimp
