// The shared half-edge mesh: quadword arrays plus one atomic status word per vertex.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "engine/huge_page_allocator.h"
#include "engine/quadword.h"
#include "engine/raw_mesh.h"

namespace femsimp {

class Mesh {
 public:
  // Validates the soup (finite coordinates, indices in range, no degenerate, duplicate or
  // non-manifold faces, consistent orientation, not empty) and builds the half-edges.
  // Errors name the problem and the first face or vertex where it occurs. raw.locked_vertices
  // (in range; unused ones are ignored) start kFixed and stay so (IsLocked).
  static absl::StatusOr<Mesh> Build(const RawMesh& raw);

  Mesh(Mesh&&) = default;
  Mesh& operator=(Mesh&&) = default;

  // The surviving vertices and faces, compacted, with their face groups and fields, and the
  // locked vertices in the new numbering. `vertex_ids`, when given, receives for each output
  // vertex its index in this mesh (= in the RawMesh it was built from).
  RawMesh ToRaw(std::vector<uint32_t>* vertex_ids = nullptr) const;

  // A vertex of RawMesh::locked_vertices: kFixed from Build on, whatever features are marked.
  bool IsLocked(uint32_t v) const { return !locked_.empty() && locked_[v] != 0; }
  // IsLocked per vertex (1: locked), or nullptr when no vertex is.
  const uint8_t* locked_flags() const { return locked_.empty() ? nullptr : locked_.data(); }
  // RawMesh::point_ids as built, or nullptr when every vertex is its own point.
  const uint32_t* point_ids() const { return point_ids_.empty() ? nullptr : point_ids_.data(); }
  // RawMesh::sides as built (engine/solid_parts.h): empty, or what lies on each side of a face,
  // indexed by SidesOf. Empty too where two faces joined across an edge have different sides.
  const std::vector<FaceSides>& sides() const { return sides_; }
  static uint32_t SidesOf(const HalfEdgeQ& h) { return h.flags >> kSidesShift; }
  // RawMesh::origin as built: positions are relative to it, and so are ToRaw's.
  const std::array<double, 3>& origin() const { return origin_; }

  // Per-face side quadwords (error bound, field values): allocated by Build when the input has
  // fields, or on demand when a tolerance is tracked (errors start at 0: the input itself).
  void EnsureFaceAttrs();
  FaceAttrQ* face_attrs() { return face_attrs_.empty() ? nullptr : face_attrs_.data(); }
  const FaceAttrQ* face_attrs() const { return face_attrs_.empty() ? nullptr : face_attrs_.data(); }
  const std::vector<std::string>& field_names() const { return field_names_; }

  // Per-vertex quadrics (quadric cost); allocated zeroed on demand.
  void EnsureQuadrics();
  QuadricQ* quadrics() { return quadrics_.empty() ? nullptr : quadrics_.data(); }

  uint32_t vertex_capacity() const { return static_cast<uint32_t>(vertices_.size()); }
  uint32_t halfedge_capacity() const { return static_cast<uint32_t>(halfedges_.size()); }
  uint32_t face_capacity() const { return halfedge_capacity() / 3; }
  size_t CountLiveVertices() const;
  size_t CountLiveFaces() const;

  VertexQ* vertices() { return vertices_.data(); }
  const VertexQ* vertices() const { return vertices_.data(); }
  HalfEdgeQ* halfedges() { return halfedges_.data(); }
  const HalfEdgeQ* halfedges() const { return halfedges_.data(); }
  std::atomic<uint32_t>* status() { return status_.get(); }
  const std::atomic<uint32_t>* status() const { return status_.get(); }

  bool IsRemoved(uint32_t v) const {
    return (status_[v].load(std::memory_order_relaxed) & kStateMask) == kRemoved;
  }
  bool IsFaceRemoved(uint32_t f) const { return halfedges_[3 * f].flags & kFaceRemoved; }

 private:
  Mesh() = default;

  HugePageVector<VertexQ> vertices_;
  HugePageVector<HalfEdgeQ> halfedges_;
  HugePageArray<std::atomic<uint32_t>> status_;
  HugePageVector<FaceAttrQ> face_attrs_;
  std::vector<std::string> field_names_;
  HugePageVector<QuadricQ> quadrics_;
  std::vector<uint8_t> locked_;      // per vertex, empty when none is locked
  std::vector<uint32_t> point_ids_;  // per vertex, empty when every vertex is its own point
  std::vector<FaceSides> sides_;
  std::array<double, 3> origin_{};
};

}  // namespace femsimp
