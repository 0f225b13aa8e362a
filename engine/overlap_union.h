// Bodies exported overlapping: a part modelled as several solids that were never fused (a boss
// standing into a plate, a rib through a wall) is exported as closed surfaces that cross each
// other. tetgen and FE meshers refuse that, and the overlap's volume counts twice. A union
// replaces each group of crossing bodies by the surface of their union (CGAL's corefinement, exact
// predicates and constructions): every facet of a body is cut where the other body's surface
// crosses it, the pieces inside another body go, and the points where the surfaces cross are
// added (rounded to float coordinates). Points of the bodies do not move.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

struct UnitedBodies {
  uint32_t first_facet = 0;    // the lowest facet of the group's bodies, in the mesh given
  std::array<double, 3> at{};  // a point where two of them cross, in the mesh's coordinates
  size_t bodies = 0;
  size_t facets_before = 0, facets_after = 0;
  size_t points_added = 0;     // where the surfaces cross
  double volume_before = 0.0;  // the bodies' volumes summed (the overlap counted twice)
  double volume_after = 0.0;   // the union's
};

// A group of crossing bodies left as it was, and why.
struct UnionLeft {
  uint32_t first_facet = 0;
  std::array<double, 3> at{};
  std::string reason;
  bool body_crosses_itself = false;  // the reason: one of its surfaces crosses itself
};

inline constexpr uint32_t kNoUnionSource = std::numeric_limits<uint32_t>::max();

struct UnionResult {
  std::vector<UnitedBodies> united;
  std::vector<UnionLeft> left;
  // Per output facet: the facet of the mesh given that it lies in; per output vertex: the
  // vertex of the mesh given, or kNoUnionSource for a point added where surfaces cross. Both
  // empty when nothing changed.
  std::vector<uint32_t> facet_origin, vertex_origin;
  RawMesh mesh;  // the mesh with the unions; empty when `united` is
};

// Unites the bodies of `mesh` that cross each other. A body is a closed, consistently oriented
// component of the mesh that bounds a positive volume (a cavity's inward wall is none); bodies
// are grouped where the crossing scan (engine/crossings.h) finds a pair of their facets that
// cross. A group is left as it was (and listed in `left`) when one of its surfaces is not such a
// body or crosses itself, when the union is not a closed surface (bodies touching along an edge
// or at a point), or when rounding the new points to floats makes facets cross. Facets of bodies
// not united keep their place and order; a group's union comes after them, each facet with the
// group and field values of the facet it lies in. The mesh given stays as it was, so that a
// caller can keep it should it refuse the union.
UnionResult UniteOverlaps(const RawMesh& mesh);

}  // namespace femsimp
