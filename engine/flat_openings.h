// The openings of a surface that lie in one plane, filled as the flat face an exporter dropped:
// repair's HoleFill::kPlanar (engine/repair.h, docs/FIDELITY.md "Repair").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace femsimp {

// The open loops of one surface (a connected component), each as its vertices in order, and
// whether repair's own small-hole fill could close it. Every loop must lie in one plane or be
// small.
struct OpeningSet {
  std::vector<std::vector<uint32_t>> loops;
  std::vector<bool> small;
};

// The loops of one plane and the facets that close them.
struct FlatFill {
  std::vector<size_t> loops;  // indices into OpeningSet::loops
  // Vertex ids, three a facet, turned as the facets along the loops ask (against their edges).
  std::vector<uint32_t> facets;
  double area = 0;
  size_t rim_edges = 0;              // the loops' edges
  size_t flush_edges = 0;            // of those, the ones whose facet lies in the fill's plane
  std::vector<uint32_t> rim_facets;  // the facets along the loops (indices, ascending, once)
};

struct FlatFillResult {
  std::vector<FlatFill> fills;  // empty when why_not is set
  std::string why_not;          // why the surface stays open ("": it closes)
};

// For each set: its loops grouped by plane (a loop that is not small starts a group; every
// loop whose corners all lie within `plane_tolerance` of that loop's plane joins it, small ones
// too, so that a face's holes go with its rim), each group filled by FillPlaneRegion
// (engine/plane_fill.h). Small loops in no group are left to the caller. A set gets no fill, and
// the reason, where a loop that is not small is not in one plane, a group's loops bound no region
// in their plane, a fill would add an edge the surface has or a facet of no area, or a fill's
// facets would cross, overlap or fold onto a facet of the surface within their box
// (engine/crossings.h). `positions` three floats a vertex, `facets` three vertex ids a facet.
std::vector<FlatFillResult> FillFlatOpenings(const std::vector<float>& positions,
                                             const std::vector<uint32_t>& facets,
                                             const std::vector<OpeningSet>& sets,
                                             double plane_tolerance);

}  // namespace femsimp
