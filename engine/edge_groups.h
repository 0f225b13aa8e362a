// The half-edges of a triangle soup grouped by undirected edge, for the passes over a soup that
// look at every face around an edge (seams, the parts of an assembly).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace femsimp {

// Corner c's successor in its face: half-edge c runs from corner c to NextCorner(c).
inline uint32_t NextCorner(uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }

// Group g holds half[begin[g] .. begin[g + 1]), ordered by (low, high, c).
struct EdgeGroups {
  std::vector<uint32_t> half, begin;

  explicit EdgeGroups(const std::vector<uint32_t>& tri) {
    const uint32_t nh = static_cast<uint32_t>(tri.size());
    struct Key {
      uint64_t edge;
      uint32_t h;
      bool operator<(const Key& o) const { return edge != o.edge ? edge < o.edge : h < o.h; }
    };
    std::vector<Key> keys(nh);
    for (uint32_t h = 0; h < nh; ++h) {
      const uint32_t a = tri[h], b = tri[NextCorner(h)];
      keys[h] = {(uint64_t{std::min(a, b)} << 32) | std::max(a, b), h};
    }
    std::sort(keys.begin(), keys.end());
    half.resize(nh);
    for (uint32_t i = 0; i < nh; ++i) {
      half[i] = keys[i].h;
      if (i == 0 || keys[i].edge != keys[i - 1].edge) begin.push_back(i);
    }
    begin.push_back(nh);
  }
  size_t size() const { return begin.size() - 1; }
  uint32_t count(size_t g) const { return begin[g + 1] - begin[g]; }
};

}  // namespace femsimp
