// How finely a mesh's positions are resolved where it lies: femsimp keeps them as 32-bit floats,
// which far from the origin are far apart, and what a file had finer than their spacing there
// was rounded away when it was read (distinct points became one, facets between them
// degenerate). Simplify reports it for every run; repair names it when nothing is left.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace femsimp {

// From here on the part has lost detail worth a warning: the spacing is 1e-4 of the part's
// size, a part some 800 to 1,700 of its diagonals from the origin.
inline constexpr double kCoarseCoordinates = 1e-4;

struct CoordinatePrecision {
  double magnitude = 0.0;  // the largest coordinate magnitude of the input
  double spacing = 0.0;    // the spacing of floats at that magnitude
  double diagonal = 0.0;   // the input's bounding-box diagonal
  double relative_spacing() const { return diagonal > 0.0 ? spacing / diagonal : 0.0; }
  // The spacing is over kCoarseCoordinates of the part's size (a part of no size: unknown).
  bool coarse() const { return relative_spacing() > kCoarseCoordinates; }
};

// Of the box [lo, hi] (three coordinates each; lo > hi on some axis: an empty box).
inline CoordinatePrecision PrecisionOfBox(const double lo[3], const double hi[3]) {
  CoordinatePrecision p;
  if (!(lo[0] <= hi[0])) return p;
  for (int k = 0; k < 3; ++k)
    p.magnitude = std::max({p.magnitude, std::fabs(lo[k]), std::fabs(hi[k])});
  const float m = static_cast<float>(p.magnitude);  // a stored coordinate: exact
  const float up = std::nextafter(m, std::numeric_limits<float>::infinity());
  // At the largest float there is none above: the spacing below is the same.
  p.spacing =
      std::isfinite(up) ? double(up) - double(m) : double(m) - double(std::nextafter(m, 0.0f));
  p.diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                         (hi[2] - lo[2]) * (hi[2] - lo[2]));
  return p;
}

}  // namespace femsimp
