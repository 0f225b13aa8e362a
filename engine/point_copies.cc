#include "engine/point_copies.h"

#include <algorithm>
#include <utility>

namespace femsimp {

PointCopies::PointCopies(const Mesh& mesh) : point_ids_(mesh.point_ids()) {
  if (point_ids_ == nullptr) return;
  std::vector<std::pair<uint32_t, uint32_t>> by_point;  // (point, vertex) of locked vertices
  for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v)
    if (mesh.IsLocked(v) && !mesh.IsRemoved(v)) by_point.emplace_back(point_ids_[v], v);
  std::sort(by_point.begin(), by_point.end());
  for (size_t i = 0; i < by_point.size();) {
    size_t j = i;
    while (j < by_point.size() && by_point[j].first == by_point[i].first) ++j;
    if (j - i >= 2) {
      index_of_point_[by_point[i].first] = static_cast<uint32_t>(offsets_.size() - 1);
      for (size_t k = i; k < j; ++k) copies_.push_back(by_point[k].second);
      offsets_.push_back(static_cast<uint32_t>(copies_.size()));
    }
    i = j;
  }
}

std::span<const uint32_t> PointCopies::Of(uint32_t p) const {
  const auto it = index_of_point_.find(p);
  if (it == index_of_point_.end()) return {};
  return copies(it->second);
}

}  // namespace femsimp
