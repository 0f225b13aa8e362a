// The copies of an assembly's seam points (engine/seams.h): SplitSeams gives every sheet meeting
// at a seam point its own vertex, locked, with the point's id (Mesh::point_ids). Copies are
// removed only all together (engine/seam_collapse.h), so the lists stay true for a whole run.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "engine/mesh.h"

namespace femsimp {

class PointCopies {
 public:
  // The live locked vertices of `mesh` by point: those of points with two copies or more.
  explicit PointCopies(const Mesh& mesh);

  // Points with copies, in point order.
  size_t size() const { return offsets_.size() - 1; }
  bool empty() const { return size() == 0; }
  std::span<const uint32_t> copies(size_t k) const {
    return {copies_.data() + offsets_[k], copies_.data() + offsets_[k + 1]};
  }
  // The copies of point p (empty when it has fewer than two).
  std::span<const uint32_t> Of(uint32_t p) const;
  // Vertex v's point (itself without point ids).
  uint32_t PointOf(uint32_t v) const { return point_ids_ == nullptr ? v : point_ids_[v]; }

 private:
  const uint32_t* point_ids_;
  std::vector<uint32_t> offsets_{0}, copies_;  // point k's copies: [offsets_[k], offsets_[k+1])
  absl::flat_hash_map<uint32_t, uint32_t> index_of_point_;
};

}  // namespace femsimp
