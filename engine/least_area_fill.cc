#include "engine/least_area_fill.h"

#include <cmath>
#include <limits>
#include <utility>

namespace femsimp {

LeastAreaFill LeastAreaTriangulation(size_t n,
                                     absl::FunctionRef<bool(size_t, size_t, size_t)> allowed,
                                     absl::FunctionRef<double(size_t, size_t, size_t)> area) {
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  LeastAreaFill fill;
  if (n < 3) {
    fill.area = HUGE_VAL;
    return fill;
  }
  // best[i][j] fills the polygon i..j, cut[i][j] is its apex.
  std::vector<double> best(n * n, 0.0);
  std::vector<uint32_t> cut(n * n, kNone);
  for (size_t span = 2; span < n; ++span)
    for (size_t i = 0; i + span < n; ++i) {
      const size_t j = i + span;
      best[i * n + j] = HUGE_VAL;
      for (size_t k = i + 1; k < j; ++k) {
        if (!allowed(i, k, j)) continue;
        const double a = best[i * n + k] + best[k * n + j] + area(i, k, j);
        if (a < best[i * n + j]) {
          best[i * n + j] = a;
          cut[i * n + j] = static_cast<uint32_t>(k);
        }
      }
    }
  fill.area = best[n - 1];
  if (fill.area == HUGE_VAL) return fill;
  std::vector<std::pair<size_t, size_t>> todo = {{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j < i + 2) continue;
    const size_t k = cut[i * n + j];
    fill.triangles.push_back({uint32_t(i), uint32_t(k), uint32_t(j)});
    todo.push_back({i, k});
    todo.push_back({k, j});
  }
  return fill;
}

}  // namespace femsimp
