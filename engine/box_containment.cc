#include "engine/box_containment.h"

#include <algorithm>
#include <cmath>

namespace femsimp {
namespace {

bool Contains(const AxisBox& outer, const AxisBox& inner) {
  for (int k = 0; k < 3; ++k)
    if (inner.lo[k] < outer.lo[k] || inner.hi[k] > outer.hi[k]) return false;
  return true;
}

}  // namespace

std::vector<std::vector<uint32_t>> ContainingBoxes(const std::vector<AxisBox>& boxes) {
  std::vector<std::vector<uint32_t>> containing(boxes.size());
  if (boxes.size() < 2) return containing;
  AxisBox all = boxes[0];
  for (const AxisBox& b : boxes)
    for (int k = 0; k < 3; ++k) {
      all.lo[k] = std::min(all.lo[k], b.lo[k]);
      all.hi[k] = std::max(all.hi[k], b.hi[k]);
    }
  // About one box per cell; a box that contains another contains its centre, so it is listed
  // in the cell of that centre.
  const int cells = std::clamp(int(std::cbrt(double(boxes.size()))), 1, 64);
  const auto cell_of = [&](double x, int k) {
    // NaN (a flat or overflowing extent) and out-of-range values are clamped before the
    // conversion.
    const double t = (x - all.lo[k]) / (all.hi[k] - all.lo[k]) * cells;
    return t >= 0 ? (t < cells ? int(t) : cells - 1) : 0;
  };
  std::vector<std::vector<uint32_t>> grid(size_t(cells) * cells * cells);
  for (uint32_t b = 0; b < boxes.size(); ++b) {
    const AxisBox& box = boxes[b];
    for (int x = cell_of(box.lo[0], 0); x <= cell_of(box.hi[0], 0); ++x)
      for (int y = cell_of(box.lo[1], 1); y <= cell_of(box.hi[1], 1); ++y)
        for (int z = cell_of(box.lo[2], 2); z <= cell_of(box.hi[2], 2); ++z)
          grid[(size_t(x) * cells + y) * cells + z].push_back(b);
  }
  for (uint32_t b = 0; b < boxes.size(); ++b) {
    const AxisBox& box = boxes[b];
    int at[3];
    for (int k = 0; k < 3; ++k) at[k] = cell_of(0.5 * (box.lo[k] + box.hi[k]), k);
    for (uint32_t other : grid[(size_t(at[0]) * cells + at[1]) * cells + at[2]])
      if (other != b && Contains(boxes[other], box)) containing[b].push_back(other);
  }
  return containing;
}

}  // namespace femsimp
