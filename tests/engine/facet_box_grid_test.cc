// The soup's box index (engine/facet_box_grid.h) finds exactly the facets a read of every facet
// finds: small and large facets mixed, flat and point boxes, queries inside, across and outside.
#include "engine/facet_box_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace femsimp {
namespace {

FacetBox Box(std::mt19937& rng, double extent, double largest) {
  std::uniform_real_distribution<double> at(-extent, extent), side(0, largest);
  FacetBox b;
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = at(rng);
    b.hi[k] = b.lo[k] + side(rng);
  }
  return b;
}

std::vector<uint32_t> Found(FacetBoxGrid& grid, const FacetBox& query) {
  std::vector<uint32_t> found;
  grid.ForEachMeeting(query, [&](uint32_t f) { found.push_back(f); });
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<uint32_t> ReadAll(const std::vector<FacetBox>& boxes, const FacetBox& query) {
  std::vector<uint32_t> found;
  for (uint32_t f = 0; f < boxes.size(); ++f)
    if (boxes[f].Meets(query)) found.push_back(f);
  return found;
}

TEST(FacetBoxGrid, FindsWhatAReadOfEveryFacetFinds) {
  std::mt19937 rng(20261206);
  std::vector<FacetBox> boxes;
  for (int i = 0; i < 20000; ++i) boxes.push_back(Box(rng, 100, 2));  // a fine tessellation
  for (int i = 0; i < 30; ++i) boxes.push_back(Box(rng, 100, 150));   // a coarse export's flats
  boxes.push_back({{5, 5, 5}, {5, 5, 5}});                            // a point
  boxes.push_back({{-3, 0, 7}, {40, 0, 9}});                          // flat in y
  FacetBoxGrid grid(boxes);
  ASSERT_EQ(grid.size(), boxes.size());
  std::vector<FacetBox> queries;
  for (int i = 0; i < 300; ++i) queries.push_back(Box(rng, 110, 6));
  for (int i = 0; i < 20; ++i) queries.push_back(Box(rng, 110, 80));
  queries.push_back({{5, 5, 5}, {5, 5, 5}});
  queries.push_back({{1000, 1000, 1000}, {1001, 1001, 1001}});  // beyond the grid
  queries.push_back({{-1e9, -1e9, -1e9}, {1e9, 1e9, 1e9}});     // around all of it
  size_t found = 0;
  for (const FacetBox& q : queries) {
    const std::vector<uint32_t> want = ReadAll(boxes, q);
    EXPECT_EQ(Found(grid, q), want);  // each once: Found keeps repeats
    found += want.size();
  }
  EXPECT_GT(found, 1000u);  // the queries meet something
}

TEST(FacetBoxGrid, ASmallQueryReadsFewEntries) {
  std::vector<FacetBox> boxes;
  for (int x = 0; x < 300; ++x)
    for (int y = 0; y < 300; ++y)
      boxes.push_back({{double(x), double(y), 0}, {x + 1.0, y + 1.0, 0}});
  FacetBoxGrid grid(boxes);
  size_t met = 0;
  const size_t read =
      grid.ForEachMeeting({{150, 150, -1}, {151, 151, 1}}, [&](uint32_t) { ++met; });
  EXPECT_EQ(met, 9u);  // the cell and its eight neighbours, which touch it
  EXPECT_LT(read, 200u) << "a query near one place read " << read << " of " << boxes.size();
}

TEST(FacetBoxGrid, EmptyAndDegenerateSoups) {
  FacetBoxGrid empty({});
  size_t met = 0;
  empty.ForEachMeeting({{0, 0, 0}, {1, 1, 1}}, [&](uint32_t) { ++met; });
  EXPECT_EQ(met, 0u);
  // Every facet at one point (a soup of zero-area facets): one cell holds them all.
  FacetBoxGrid point(std::vector<FacetBox>(50, FacetBox{{2, 2, 2}, {2, 2, 2}}));
  point.ForEachMeeting({{2, 2, 2}, {3, 3, 3}}, [&](uint32_t) { ++met; });
  EXPECT_EQ(met, 50u);
}

}  // namespace
}  // namespace femsimp
