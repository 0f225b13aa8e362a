// Facets of a surface that cross each other, taken out and the hole closed again: a vertex an
// exporter wrote wrongly (its facets poke through the part's far wall), two faces tessellated
// apart whose chords cross where they meet at a small angle. No point moves: the facets around
// the crossing come out as a patch bounded by one simple loop (a disc), and the loop is closed by
// its triangulation of least area that adds no edge the mesh has; a patch whose fill still
// crosses something grows by a ring of facets and is tried again (up to kMaxRings rings).
//
// Left as they are, with a reason: crossings between two surfaces (bodies exported overlapping:
// which one is wrong the mesh cannot tell), patches that reach an open edge or a seam, that are
// not discs, whose loop is longer than kMaxLoopEdges, whose facets take more than kMaxPatchShare
// or whose fill would take more than kMaxFillShare of their surface's area (a thin wall
// tessellated coarser than its thickness: docs/FIDELITY.md § 9), and patches no growth frees of
// crossings.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

inline constexpr int kMaxRings = 3;
inline constexpr size_t kMaxLoopEdges = 64;
inline constexpr double kMaxFillShare = 0.02;
inline constexpr double kMaxPatchShare = 0.05;  // of the facets a grown patch takes out
// A vertex's facets on a coarse export span a face: its removal may close a larger share.
inline constexpr double kMaxVertexFillShare = 0.25;

struct UncrossedPatch {
  uint32_t first_facet = 0;    // the lowest facet (of the mesh given) it took out
  std::array<double, 3> at{};  // its lowest facet's centroid (relative to the mesh's origin)
  size_t facets_removed = 0, facets_added = 0, loop_edges = 0, vertices_dropped = 0;
  double area_removed = 0, area_added = 0;
  double volume_change = 0;  // of the region its surface encloses: added facets' less removed
  double farthest = 0;       // the largest distance of a dropped vertex from the new facets
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
};

// `mesh`: a repaired surface (welded, oriented, one fan per vertex). Its vertices stay as they
// are (those only the patches used are left unreferenced); facets taken out go, new ones are
// appended. Where the patches taken out leave no fewer crossing pairs than there were, nothing
// changes.
UncrossResult TakeOutCrossings(RawMesh& mesh);

}  // namespace femsimp
