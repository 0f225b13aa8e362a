#include "engine/facet_box_grid.h"

#include <algorithm>
#include <cmath>

namespace femsimp {
namespace {

double LongestSide(const FacetBox& b) {
  return std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
}

}  // namespace

FacetBoxGrid::FacetBoxGrid(std::vector<FacetBox> boxes) : boxes_(std::move(boxes)) {
  const size_t n = boxes_.size();
  seen_.assign(n, 0);
  begin_.assign(2, 0);  // one empty cell
  if (n == 0) return;
  FacetBox bounds = boxes_[0];
  for (const FacetBox& b : boxes_)
    for (int k = 0; k < 3; ++k) {
      bounds.lo[k] = std::min(bounds.lo[k], b.lo[k]);
      bounds.hi[k] = std::max(bounds.hi[k], b.hi[k]);
    }
  std::vector<double> sides(n);
  for (size_t f = 0; f < n; ++f) sides[f] = LongestSide(boxes_[f]);
  std::nth_element(sides.begin(), sides.begin() + n / 2, sides.end());
  double cell = 2 * sides[n / 2];
  const double extent = LongestSide(bounds);
  if (!(cell > 0)) cell = extent > 0 ? extent / std::cbrt(double(n)) : 1;
  // At most about four cells per facet: a few large facets among many small ones (or a thin
  // part's bounds) must not make the grid's table larger than the soup.
  const auto cells_along = [&](int k) {
    return std::max<int64_t>(1, int64_t(std::ceil((bounds.hi[k] - bounds.lo[k]) / cell)));
  };
  const double most = 4.0 * double(n) + 64;
  for (;;) {
    const double cells = double(cells_along(0)) * double(cells_along(1)) * double(cells_along(2));
    if (cells <= most) break;
    cell *= std::max(1.01, std::cbrt(cells / most));
  }
  origin_ = bounds.lo;
  inverse_cell_ = 1 / cell;
  dims_ = {cells_along(0), cells_along(1), cells_along(2)};
  const size_t num_cells = size_t(dims_[0] * dims_[1] * dims_[2]);

  // Counted, then placed: one pass over the facets each.
  begin_.assign(num_cells + 1, 0);
  std::vector<char> wide(n, 0);
  std::array<int64_t, 3> a, b;
  for (size_t f = 0; f < n; ++f) {
    const bool inside = CellRange(boxes_[f], &a, &b);  // always, but for NaN coordinates
    if (!inside || (b[0] - a[0] + 1) * (b[1] - a[1] + 1) * (b[2] - a[2] + 1) > kMaxCellsPerFacet) {
      wide[f] = 1;
      wide_.push_back(uint32_t(f));
      continue;
    }
    for (int64_t z = a[2]; z <= b[2]; ++z)
      for (int64_t y = a[1]; y <= b[1]; ++y)
        for (int64_t x = a[0]; x <= b[0]; ++x) ++begin_[Cell(x, y, z) + 1];
  }
  for (size_t c = 0; c < num_cells; ++c) begin_[c + 1] += begin_[c];
  entries_.resize(begin_[num_cells]);
  std::vector<size_t> fill(begin_.begin(), begin_.end() - 1);
  for (size_t f = 0; f < n; ++f) {
    if (wide[f]) continue;
    CellRange(boxes_[f], &a, &b);
    for (int64_t z = a[2]; z <= b[2]; ++z)
      for (int64_t y = a[1]; y <= b[1]; ++y)
        for (int64_t x = a[0]; x <= b[0]; ++x) entries_[fill[Cell(x, y, z)]++] = uint32_t(f);
  }
}

bool FacetBoxGrid::CellRange(const FacetBox& box, std::array<int64_t, 3>* a,
                             std::array<int64_t, 3>* b) const {
  for (int k = 0; k < 3; ++k) {
    // In doubles first: a box far outside the grid must not overflow the integer cast.
    const double lo = std::floor((box.lo[k] - origin_[k]) * inverse_cell_);
    const double hi = std::floor((box.hi[k] - origin_[k]) * inverse_cell_);
    if (!(hi >= 0) || !(lo < double(dims_[k]))) return false;  // outside, or NaN
    (*a)[k] = lo < 0 ? 0 : int64_t(lo);
    (*b)[k] = std::min<int64_t>(dims_[k] - 1, int64_t(hi));
  }
  return true;
}

}  // namespace femsimp
