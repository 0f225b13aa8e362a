#include "engine/surfaces.h"

#include <limits>

namespace femsimp {

Surfaces FindSurfaces(std::span<const uint32_t> tri, std::span<const uint32_t> edge_of,
                      std::span<const uint32_t> edge_uses) {
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  const uint32_t nf = static_cast<uint32_t>(tri.size() / 3);
  std::vector<uint32_t> partner(3 * size_t(nf), kNone);  // the other half-edge of a two-facet edge
  {
    std::vector<uint32_t> first_half(edge_uses.size(), kNone);
    for (uint32_t h = 0; h < 3 * nf; ++h) {
      const uint32_t e = edge_of[h];
      if (edge_uses[e] != 2) continue;
      if (first_half[e] == kNone) {
        first_half[e] = h;
      } else {
        partner[h] = first_half[e];
        partner[first_half[e]] = h;
      }
    }
  }
  Surfaces s;
  s.of_facet.assign(nf, kNone);
  s.parity.assign(nf, 0);
  std::vector<uint32_t> queue;
  for (uint32_t seed = 0; seed < nf; ++seed) {
    if (s.of_facet[seed] != kNone) continue;
    const uint32_t id = s.count();
    s.orientable.push_back(1);
    s.of_facet[seed] = id;
    queue.assign(1, seed);
    for (size_t q = 0; q < queue.size(); ++q) {
      const uint32_t x = queue[q];
      for (uint32_t h = 3 * x; h < 3 * x + 3; ++h) {
        const uint32_t g = partner[h];
        if (g == kNone) continue;
        const uint32_t y = g / 3;
        const uint8_t want = s.parity[x] ^ uint8_t(tri[h] == tri[g]);
        if (s.of_facet[y] == kNone) {
          s.of_facet[y] = id;
          s.parity[y] = want;
          queue.push_back(y);
        } else if (s.parity[y] != want) {
          s.orientable[id] = 0;
        }
      }
    }
  }
  return s;
}

}  // namespace femsimp
