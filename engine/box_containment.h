// Which boxes contain which: for the shells of a mesh, the candidates that may enclose each one
// (a shell inside another lies inside its box). A uniform grid on the boxes answers it, so that
// a soup of many small parts (an assembly of fasteners, a particle packing) costs a few box
// tests per part instead of one per pair.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace femsimp {

struct AxisBox {
  std::array<double, 3> lo, hi;
};

// For each box, the indices (ascending) of the other boxes that contain it, faces included.
std::vector<std::vector<uint32_t>> ContainingBoxes(const std::vector<AxisBox>& boxes);

}  // namespace femsimp
