// The facets of a soup whose boxes meet a query box, found through a uniform grid of their boxes
// instead of a read of every facet: a repair that tries many small fills on a mesh of a million
// facets asks for each fill's surroundings, and a whole read per try made it quadratic.
//
// Cells are about twice the median facet's longest side (a few facets each), their number at
// most a few per facet. A facet whose box spans more than kMaxCellsPerFacet cells (a large
// planar facet of a coarse CAD export) is kept in a list every query reads.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace femsimp {

struct FacetBox {
  std::array<double, 3> lo, hi;
  bool Meets(const FacetBox& o) const {
    return lo[0] <= o.hi[0] && hi[0] >= o.lo[0] && lo[1] <= o.hi[1] && hi[1] >= o.lo[1] &&
           lo[2] <= o.hi[2] && hi[2] >= o.lo[2];
  }
};

// The box of the facet with corners c[0..2] in `positions` (x, y, z per vertex).
inline FacetBox FacetBoxOf(const std::vector<float>& positions, const uint32_t* c) {
  FacetBox b{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min(b.lo[k], double{positions[3 * size_t{c[i]} + k]});
      b.hi[k] = std::max(b.hi[k], double{positions[3 * size_t{c[i]} + k]});
    }
  return b;
}

class FacetBoxGrid {
 public:
  static constexpr int64_t kMaxCellsPerFacet = 64;

  explicit FacetBoxGrid(std::vector<FacetBox> boxes);

  // Calls visit(f) once for every facet f whose box meets `box`, in no fixed order; returns the
  // number of facet entries read (the query's work). Not for concurrent use (it marks facets).
  template <class Visit>
  size_t ForEachMeeting(const FacetBox& box, Visit&& visit) {
    size_t read = 0;
    const auto offer = [&](uint32_t f) {
      ++read;
      if (seen_[f] == stamp_ || !boxes_[f].Meets(box)) return;
      seen_[f] = stamp_;
      visit(f);
    };
    if (++stamp_ == 0) {  // wrapped: no facet may carry the new stamp
      std::fill(seen_.begin(), seen_.end(), 0);
      stamp_ = 1;
    }
    for (uint32_t f : wide_) offer(f);
    if (boxes_.empty()) return read;
    std::array<int64_t, 3> a, b;
    if (!CellRange(box, &a, &b)) return read;
    for (int64_t z = a[2]; z <= b[2]; ++z)
      for (int64_t y = a[1]; y <= b[1]; ++y)
        for (int64_t x = a[0]; x <= b[0]; ++x) {
          const size_t c = Cell(x, y, z);
          for (size_t i = begin_[c]; i < begin_[c + 1]; ++i) offer(entries_[i]);
        }
    return read;
  }

  size_t size() const { return boxes_.size(); }

 private:
  // The cells a box spans, clamped to the grid; false where it misses the grid.
  bool CellRange(const FacetBox& box, std::array<int64_t, 3>* a, std::array<int64_t, 3>* b) const;
  size_t Cell(int64_t x, int64_t y, int64_t z) const {
    return size_t((z * dims_[1] + y) * dims_[0] + x);
  }

  std::vector<FacetBox> boxes_;
  std::array<double, 3> origin_{};
  double inverse_cell_ = 1;
  std::array<int64_t, 3> dims_{1, 1, 1};
  std::vector<size_t> begin_;      // per cell, into entries_ (one more than the cells)
  std::vector<uint32_t> entries_;  // facets by cell
  std::vector<uint32_t> wide_;     // facets over kMaxCellsPerFacet cells
  std::vector<uint32_t> seen_;
  uint32_t stamp_ = 0;
};

}  // namespace femsimp
