// The triangulation of least area of a small polygon: how repair closes a hole of a few missing
// facets, and the notch a dropped facet beside a dropped flat face leaves.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "absl/functional/function_ref.h"

namespace femsimp {

struct LeastAreaFill {
  // Corner indices (i, k, j), i < k < j, of each triangle; empty where no triangulation is allowed.
  std::vector<std::array<uint32_t, 3>> triangles;
  double area = 0;  // their total; HUGE_VAL where none is allowed
};

// Over the polygon of corners 0 .. n - 1 (cubic in n: meant for a few corners): `allowed(i, k,
// j)` says whether triangle (i, k, j) may be used (its sides that are not polygon edges new, its
// area not zero), `area(i, k, j)` its area. The triangles come cut from the closing edge (0,
// n - 1) inwards: first the one on that edge, then depth first, the part before its apex last.
LeastAreaFill LeastAreaTriangulation(size_t n,
                                     absl::FunctionRef<bool(size_t, size_t, size_t)> allowed,
                                     absl::FunctionRef<double(size_t, size_t, size_t)> area);

}  // namespace femsimp
