// Bodies exported apart that touch: each body's facets triangulate the contact on their own, so
// the contact is covered twice, by facets that overlap in one plane (engine/planar_overlap.h).
// tetgen and most FE meshers refuse that. An imprint re-tiles each such contact as gmsh's fragment
// writes one: the two bodies' facets there are replaced by one triangulation of their common
// refinement (every edge of either body kept, cut where the bodies' edges cross), whose part
// covered by both bodies is written once, shared by the two (its edges along the contact's rim
// become seams: engine/seams.h, engine/solid_parts.h) and whose parts covered by one body stay
// that body's. Facets of either body that meet the contact along an edge it cut are split at the
// new points, so the surface stays conforming. Points are added only where edges cross (in the
// contact's plane); no point moves, except that a corner of one body that coincides with a corner
// of the other in the plane (within the plane's tolerance, not the weld's) becomes that corner.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

struct ImprintedContact {
  uint32_t first_facet = 0;    // the lowest facet of the contact, in the mesh given
  std::array<double, 3> at{};  // the centroid of the shared part, in the mesh's coordinates
  double area = 0.0;           // of the shared part
  size_t facets_before = 0;    // facets of either body that covered the contact
  size_t facets_after = 0;     // facets that replaced them (the shared ones once)
  size_t shared_facets = 0;    // of those, covered by both bodies
  size_t points_added = 0;     // where the bodies' edges cross
  size_t corners_merged = 0;   // corners of one body that coincide with the other's
};

// A contact left as it was, and why.
struct ContactLeft {
  uint32_t first_facet = 0;
  std::array<double, 3> at{};  // a corner of its first facet
  std::string reason;
};

inline constexpr uint32_t kNoSourceVertex = std::numeric_limits<uint32_t>::max();

struct ImprintResult {
  std::vector<ImprintedContact> contacts;
  std::vector<ContactLeft> left;
  size_t neighbours_split = 0;  // facets outside the contacts split at the new points
  // Per output facet: the facet of the mesh given that it lies in (for a shared facet: the lower
  // of the two). Per output vertex: the vertex of the mesh given, or kNoSourceVertex for a point
  // added where edges cross. Both empty when nothing changed.
  std::vector<uint32_t> facet_origin, vertex_origin;
};

// Imprints every planar contact of `mesh` (positions, triangles, face groups and fields; the
// contacts are found by FindCrossings' overlap test, engine/crossings.h). The bodies' facets
// there must face opposite ways (they touch from outside); a contact whose facets overlap facing
// the same way, or cover a point three times, is left as it was and listed in `left`. The
// re-tiled facets come after the others; split facets keep their place (their first piece) with
// the other pieces after them. A mesh without contacts is not touched.
ImprintResult ImprintContacts(RawMesh& mesh);

}  // namespace femsimp
