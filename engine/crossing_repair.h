// Facets that cross each other, taken out and the hole closed again, where a vertex written
// wrongly made them (a digit lost: its facets poke through the part's far wall, into a cavity or
// another body). No point moves: per cluster of crossing facets (linked by their pairs), the
// vertex whose facets hold a facet of every pair goes with its facets, and its ring (a simple
// loop: the facets a disc) is closed by its triangulation of least area that adds no edge the
// mesh has, every new facet turning the ring's way seen along its normal; of several such vertices,
// the one farthest off its ring (a vertex of a surface lies near its ring's middle, one written
// wrongly far off it). Where no one vertex does, the vertices farthest off their rings are taken
// out together until their facets hold every pair. A fill that would cross, overlap or fold onto
// anything near it is not made.
//
// Left as they are, with a reason: crossings no vertex taken out frees (a thin wall tessellated
// coarser than its thickness, bodies exported overlapping: which one is off the mesh cannot
// tell), rims that reach an open edge or a seam, that are not one simple loop, that are longer
// than kMaxLoopEdges or whose fill would take more than kMaxFillShare of its surface's area.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

inline constexpr size_t kMaxLoopEdges = 64;
// A vertex's facets on a coarse export span a face: their rim may close a large share of it.
inline constexpr double kMaxFillShare = 0.25;

struct UncrossedPatch {
  uint32_t first_facet = 0;    // the lowest facet (of the mesh given) it took out
  std::array<double, 3> at{};  // its lowest facet's centroid (relative to the mesh's origin)
  size_t facets_removed = 0, facets_added = 0, loop_edges = 0, vertices_dropped = 0;
  double area_removed = 0, area_added = 0;
  double volume_change = 0;  // of the region its surface encloses: added facets' less removed
  double farthest = 0;       // the largest distance of a dropped vertex from the new facets
  double across = 0;         // the rim's largest extent: where the surface was rebuilt
};

struct CrossingLeft {
  uint32_t first_facet = 0;  // of the mesh given
  std::array<double, 3> at{};
  std::string reason;
};

struct UncrossResult {
  size_t pairs_before = 0, pairs_after = 0;  // face pairs that certainly cross
  std::vector<UncrossedPatch> patches;
  std::vector<CrossingLeft> left;
  // Per facet of the result: the facet of the mesh given it is (a new facet: the facet taken out
  // nearest to it, whose group and fields it took). Empty where nothing changed.
  std::vector<uint32_t> facet_origin;
  // Where facet_origin is not empty: the mesh given with its vertices as they are (those taken
  // out left unreferenced), the facets taken out gone and the new ones appended.
  RawMesh mesh;
};

// Which crossing pairs are taken out: all, or only those of facets of one surface (before the
// union of bodies exported overlapping, which takes no body that crosses itself: the pairs
// between two surfaces are the union's, and are neither taken out nor reported).
enum class CrossingScope { kAll, kWithinSurfaces };

// `mesh`: a repaired surface (welded, oriented, one fan per vertex); it is not changed. Where
// what would be taken out leaves no fewer crossing pairs than there were, nothing is.
// The scan for crossing pairs runs on `threads` threads.
UncrossResult TakeOutCrossings(const RawMesh& mesh, int threads = 1,
                               CrossingScope scope = CrossingScope::kAll);

}  // namespace femsimp
