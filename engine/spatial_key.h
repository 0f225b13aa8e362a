// A point's place along a Z-order (Morton) curve through a box: points close in space get close
// keys, so contiguous ranges of the key order are compact regions of the mesh.
#pragma once

#include <algorithm>
#include <cstdint>

#include "engine/quadword.h"

namespace femsimp {

// The Morton code of a cell of a 1024^3 grid: the three 10-bit coordinates' bits interleaved,
// x in the lowest bit of each triple.
inline uint32_t Morton3(uint32_t x, uint32_t y, uint32_t z) {
  const auto spread = [](uint32_t v) {  // the 10 bits of v to every third bit
    v &= 0x3ffu;
    v = (v | (v << 16)) & 0x30000ffu;
    v = (v | (v << 8)) & 0x300f00fu;
    v = (v | (v << 4)) & 0x30c30c3u;
    v = (v | (v << 2)) & 0x9249249u;
    return v;
  };
  return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

class SpatialKey {
 public:
  static constexpr int kBitsPerAxis = 10;  // 30 bits in all: a 1024^3 grid over the box

  // The box of the vertices [0, count), removed ones included (they keep their last place).
  SpatialKey(const VertexQ* vertices, uint32_t count) {
    for (uint32_t v = 0; v < count; ++v) {
      const float p[3] = {vertices[v].x, vertices[v].y, vertices[v].z};
      for (int a = 0; a < 3; ++a) {
        lo_[a] = std::min(lo_[a], p[a]);
        hi_[a] = std::max(hi_[a], p[a]);
      }
    }
  }

  // The key of q; a point outside the box (a vertex moved by a full-edge collapse) is clamped.
  uint32_t operator()(const VertexQ& q) const {
    const float p[3] = {q.x, q.y, q.z};
    uint32_t cell[3];
    for (int a = 0; a < 3; ++a) {
      const float extent = hi_[a] - lo_[a];
      const float t = extent > 0.0f ? std::clamp((p[a] - lo_[a]) / extent, 0.0f, 1.0f) : 0.0f;
      cell[a] = std::min(kCells - 1, static_cast<uint32_t>(t * float(kCells)));
    }
    return Morton3(cell[0], cell[1], cell[2]);
  }

 private:
  static constexpr uint32_t kCells = 1u << kBitsPerAxis;
  float lo_[3] = {1e30f, 1e30f, 1e30f}, hi_[3] = {-1e30f, -1e30f, -1e30f};
};

}  // namespace femsimp
