// Whether points lie inside a closed, consistently oriented shell, fast enough to ask for every
// cavity of a part with thousands of pores: a ray along +x from the point, its crossings with
// the shell counted with their sign (the winding number), the facets found through a grid on
// their projections. Where the ray meets an edge or a vertex in projection, the point is moved
// symbolically by (0, ε, ε²), and each edge's test is computed the same way in both facets that
// share it, so that every crossing counts exactly once.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/vec.h"

namespace femsimp {

class PointInShell {
 public:
  // `corners`: three vertex ids per facet, oriented consistently; `positions`: x, y, z per vertex
  // id (it must outlive this).
  PointInShell(const float* positions, std::vector<uint32_t> corners);
  // The winding number about p: ±1 inside (the sign is the shell's orientation), 0 outside.
  int Winding(const DVec3& p) const;

 private:
  DVec3 Position(uint32_t v) const;
  int Cell(double x, int axis) const;  // axis 0: y, 1: z

  const float* positions_;
  std::vector<uint32_t> corners_;
  std::array<double, 2> lo_{}, hi_{};
  int cells_ = 1;
  std::vector<uint32_t> cell_begin_, cell_facets_;  // facets per cell, as offsets into the list
};

}  // namespace femsimp
