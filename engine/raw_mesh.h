// Indexed triangle soup: the exchange format between file I/O, the wire format and the engine.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace femsimp {

// A per-face scalar carried through the simplification, e.g. a pressure. The engine treats it as
// a traction normal to the face and keeps its resultant (sum of value * area vector) per face
// group (docs/FIDELITY.md).
struct FaceField {
  std::string name;
  std::vector<float> values;  // one per face
};

inline constexpr size_t kMaxFaceFields = 3;  // they share one 16-byte quadword with the error bound

// Which solid part of an assembly lies on each side of a face (engine/solid_parts.h); kSpace:
// none. `weight` is the face's share in the whole solid's integrals: +1 where its normal points
// out of the solid, -1 where it points in, 0 where solid or space lies on both sides (the
// interface between two parts).
inline constexpr int32_t kSpace = -1;
struct FaceSides {
  int32_t behind = kSpace;  // against the normal
  int32_t ahead = kSpace;   // where the normal points
  int32_t weight = 1;
  bool operator==(const FaceSides&) const = default;
};

struct RawMesh {
  std::vector<float> positions;        // x, y, z per vertex, relative to `origin`
  std::vector<uint32_t> triangles;     // three vertex indices per face, counter-clockwise
  std::vector<uint32_t> face_groups;   // empty, or one group id per face
  std::vector<FaceField> face_fields;  // at most kMaxFaceFields
  // Vertices the simplification must leave exactly where they are: never removed, never moved
  // (a neighbour may still collapse onto one). Mesh::Build marks them; Mesh::ToRaw lists the
  // survivors in its numbering. Seams of assemblies (engine/seams.h) are kept this way.
  std::vector<uint32_t> locked_vertices{};
  // Empty, or per vertex the point it stands at: vertices with the same id are copies of one
  // point (the seam copies SplitSeams makes), at the same coordinates. The self-intersection
  // rule treats copies as one vertex, so that sheets meeting at a seam touch there and only
  // there. Mesh::Build checks them; Mesh::ToRaw does not list them.
  std::vector<uint32_t> point_ids{};
  // Empty, or per face an index into `sides` (engine/solid_parts.h): the parts of an assembly
  // that meet at seams, each a solid. Mesh::Build checks them.
  std::vector<uint32_t> face_sides{};
  std::vector<FaceSides> sides{};
  // Where positions are measured from: a vertex lies at origin + its position in the file's
  // coordinates. Not 0 only for parts far from the origin (engine/local_origin.h); what comes
  // out of a mesh keeps its input's origin.
  std::array<double, 3> origin{};

  size_t num_vertices() const { return positions.size() / 3; }
  size_t num_faces() const { return triangles.size() / 3; }
};

}  // namespace femsimp
