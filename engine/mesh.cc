#include "engine/mesh.h"

#include <algorithm>
#include <memory>

#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "engine/mesh_checks.h"

namespace femsimp {

absl::StatusOr<Mesh> Mesh::Build(const RawMesh& raw) {
  if (absl::Status s = CheckSoup(raw); !s.ok()) return s;
  const uint32_t nv = static_cast<uint32_t>(raw.num_vertices());
  const uint32_t nh = static_cast<uint32_t>(raw.triangles.size());

  // Outgoing half-edges per vertex (compressed rows): source(h) = triangles[prev(h)].
  std::vector<uint32_t> first(nv + 1, 0), outgoing(nh);
  for (uint32_t h = 0; h < nh; ++h) ++first[raw.triangles[Prev(h)] + 1];
  for (uint32_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  {
    std::vector<uint32_t> fill(first.begin(), first.end() - 1);
    for (uint32_t h = 0; h < nh; ++h) outgoing[fill[raw.triangles[Prev(h)]]++] = h;
  }
  const auto target = [&](uint32_t h) { return raw.triangles[h]; };

  Mesh mesh;
  mesh.halfedges_.resize(nh);
  for (uint32_t h = 0; h < nh; ++h) {
    const uint32_t a = raw.triangles[Prev(h)], b = target(h);
    uint32_t twin = kNone;
    for (uint32_t i = first[a]; i < first[a + 1]; ++i) {
      uint32_t g = outgoing[i];
      if (g != h && target(g) == b) {
        uint32_t nfaces = 0;  // faces on the undirected edge, for the message
        for (uint32_t j = first[a]; j < first[a + 1]; ++j) nfaces += target(outgoing[j]) == b;
        for (uint32_t j = first[b]; j < first[b + 1]; ++j) nfaces += target(outgoing[j]) == a;
        if (nfaces > 2)
          return absl::InvalidArgumentError(
              absl::StrCat("non-manifold edge (", a, ", ", b, "): shared by ", nfaces, " faces"));
        return absl::InvalidArgumentError(
            absl::StrCat("faces ", FaceOf(h), " and ", FaceOf(g), " both use edge (", a, ", ", b,
                         ") in the same direction: inconsistent orientation or duplicate face"));
      }
    }
    for (uint32_t i = first[b]; i < first[b + 1]; ++i)
      if (target(outgoing[i]) == a) twin = outgoing[i];
    const uint32_t f = FaceOf(h);
    mesh.halfedges_[h] = {b, twin, raw.face_groups.empty() ? 0u : raw.face_groups[f], 0u};
  }
  // Two faces on the same three vertices, oppositely oriented, make a closed pillow that the
  // twin matching alone accepts.
  for (uint32_t f = 0; f < nh / 3; ++f) {
    const uint32_t t0 = mesh.halfedges_[3 * f].twin;
    if (t0 == kNone) continue;
    if (FaceOf(mesh.halfedges_[3 * f + 1].twin) == FaceOf(t0) &&
        FaceOf(mesh.halfedges_[3 * f + 2].twin) == FaceOf(t0) &&
        mesh.halfedges_[3 * f + 1].twin != kNone && mesh.halfedges_[3 * f + 2].twin != kNone)
      return absl::InvalidArgumentError(
          absl::StrCat("faces ", f, " and ", FaceOf(t0), " are duplicates (same three vertices)"));
  }

  mesh.vertices_.resize(nv);
  mesh.status_ = MakeHugePageArray<std::atomic<uint32_t>>(nv);
  for (uint32_t v = 0; v < nv; ++v) {
    VertexQ& q = mesh.vertices_[v];
    q = {raw.positions[3 * v], raw.positions[3 * v + 1], raw.positions[3 * v + 2], kNone};
    const uint32_t degree = first[v + 1] - first[v];
    if (degree == 0) {  // isolated vertex: not part of the surface, dropped from the output
      mesh.status_[v].store(kRemoved, std::memory_order_relaxed);
      continue;
    }
    uint32_t boundary_out = kNone, boundary_count = 0;
    for (uint32_t i = first[v]; i < first[v + 1]; ++i)
      if (mesh.halfedges_[outgoing[i]].twin == kNone) {
        boundary_out = outgoing[i];
        ++boundary_count;
      }
    if (boundary_count > 1)
      return absl::InvalidArgumentError(absl::StrCat(
          "vertex ", v, " is non-manifold: ", boundary_count, " boundary fans meet there"));
    // One sweep counter-clockwise from the clockwise-most edge must reach every face.
    const uint32_t start = boundary_out != kNone ? boundary_out : outgoing[first[v]];
    uint32_t h = start, reached = 0;
    do {
      ++reached;
      h = mesh.halfedges_[Prev(h)].twin;
    } while (h != kNone && h != start && reached <= degree);
    if (reached != degree)
      return absl::InvalidArgumentError(absl::StrCat("vertex ", v, " is non-manifold: its ", degree,
                                                     " faces form more than one fan"));
    q.out = start;
    mesh.status_[v].store(kRemovable, std::memory_order_relaxed);
  }
  if (!raw.locked_vertices.empty()) {
    mesh.locked_.assign(nv, 0);
    for (const uint32_t v : raw.locked_vertices) {
      if (v >= nv)
        return absl::InvalidArgumentError(
            absl::StrCat("locked vertex ", v, " out of range (", nv, " vertices)"));
      if (mesh.status_[v].load(std::memory_order_relaxed) == kRemoved) continue;  // unused
      mesh.locked_[v] = 1;
      mesh.status_[v].store(kFixed, std::memory_order_relaxed);
    }
  }
  if (!raw.point_ids.empty()) {
    if (raw.point_ids.size() != nv)
      return absl::InvalidArgumentError(absl::StrCat("point ids: ", raw.point_ids.size(), " for ",
                                                     nv, " vertices (one per vertex)"));
    absl::flat_hash_map<uint32_t, uint32_t> first;  // point id -> its first vertex
    for (uint32_t v = 0; v < nv; ++v) {
      const auto [it, fresh] = first.try_emplace(raw.point_ids[v], v);
      const uint32_t u = it->second;
      if (!fresh &&
          !std::equal(&raw.positions[3 * u], &raw.positions[3 * u + 3], &raw.positions[3 * v]))
        return absl::InvalidArgumentError(absl::StrCat(
            "point ids: vertices ", u, " and ", v, " share point id ", raw.point_ids[v],
            " but lie at (", raw.positions[3 * u], ", ", raw.positions[3 * u + 1], ", ",
            raw.positions[3 * u + 2], ") and (", raw.positions[3 * v], ", ",
            raw.positions[3 * v + 1], ", ", raw.positions[3 * v + 2], ")"));
    }
    mesh.point_ids_ = raw.point_ids;
  }
  if (!raw.face_sides.empty() || !raw.sides.empty()) {
    if (raw.face_sides.size() != nh / 3 || raw.sides.size() >= kMaxSides)
      return absl::InvalidArgumentError(
          absl::StrCat("face sides: ", raw.face_sides.size(), " for ", nh / 3, " faces, ",
                       raw.sides.size(), " entries (one per face; fewer than ", kMaxSides, ")"));
    for (uint32_t h = 0; h < nh; ++h) {
      const uint32_t s = raw.face_sides[FaceOf(h)];
      if (s >= raw.sides.size())
        return absl::InvalidArgumentError(absl::StrCat("face ", FaceOf(h), ": sides ", s,
                                                       " out of range (", raw.sides.size(), ")"));
      mesh.halfedges_[h].flags |= s << kSidesShift;
    }
    // A collapse rewrites faces joined across edges, which must see the same parts. A sheet
    // that closes a fan around both ends of a seam edge stays joined there (engine/seams.h)
    // while the wedges of space around the edge may part its two faces' sides: such an
    // assembly is measured as a surface.
    bool agree = true;
    for (uint32_t h = 0; h < nh && agree; ++h) {
      const uint32_t t = mesh.halfedges_[h].twin;
      agree = t == kNone || raw.face_sides[FaceOf(h)] == raw.face_sides[FaceOf(t)];
    }
    if (agree)
      mesh.sides_ = raw.sides;
    else
      for (HalfEdgeQ& h : mesh.halfedges_) h.flags &= (1u << kSidesShift) - 1;
  }
  mesh.origin_ = raw.origin;
  if (!raw.face_fields.empty()) {
    mesh.EnsureFaceAttrs();
    for (size_t i = 0; i < raw.face_fields.size(); ++i) {
      mesh.field_names_.push_back(raw.face_fields[i].name);
      for (uint32_t f = 0; f < nh / 3; ++f)
        mesh.face_attrs_[f].field[i] = raw.face_fields[i].values[f];
    }
  }
  return mesh;
}

void Mesh::EnsureFaceAttrs() {
  if (face_attrs_.empty()) face_attrs_.assign(face_capacity(), FaceAttrQ{});
}

void Mesh::EnsureQuadrics() {
  if (quadrics_.empty()) quadrics_.assign(vertex_capacity(), QuadricQ{});
}

RawMesh Mesh::ToRaw(std::vector<uint32_t>* vertex_ids) const {
  RawMesh raw;
  raw.origin = origin_;
  std::vector<uint32_t> remap(vertices_.size(), kNone);
  uint32_t next = 0;
  if (vertex_ids != nullptr) vertex_ids->clear();
  for (uint32_t v = 0; v < vertices_.size(); ++v) {
    if (IsRemoved(v)) continue;
    remap[v] = next++;
    raw.positions.insert(raw.positions.end(), {vertices_[v].x, vertices_[v].y, vertices_[v].z});
    if (vertex_ids != nullptr) vertex_ids->push_back(v);
    if (IsLocked(v)) raw.locked_vertices.push_back(remap[v]);
  }
  bool any_group = false;
  for (const std::string& name : field_names_) raw.face_fields.push_back({name, {}});
  for (uint32_t f = 0; f < face_capacity(); ++f) {
    if (IsFaceRemoved(f)) continue;
    for (int i = 0; i < 3; ++i) raw.triangles.push_back(remap[halfedges_[3 * f + i].target]);
    raw.face_groups.push_back(halfedges_[3 * f].group);
    any_group |= halfedges_[3 * f].group != 0;
    for (size_t i = 0; i < field_names_.size(); ++i)
      raw.face_fields[i].values.push_back(face_attrs_[f].field[i]);
  }
  if (!any_group) raw.face_groups.clear();
  return raw;
}

size_t Mesh::CountLiveVertices() const {
  size_t n = 0;
  for (uint32_t v = 0; v < vertices_.size(); ++v) n += !IsRemoved(v);
  return n;
}

size_t Mesh::CountLiveFaces() const {
  size_t n = 0;
  for (uint32_t f = 0; f < face_capacity(); ++f) n += !IsFaceRemoved(f);
  return n;
}

}  // namespace femsimp
