// The openings of a surface that lie in one plane, filled as the flat face an exporter dropped:
// repair's HoleFill::kPlanar (engine/repair.h, docs/FIDELITY.md "Repair").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace femsimp {

// An open loop: its vertices in order, the surface (connected component) it bounds, and whether
// repair's own small-hole fill could close it.
struct OpeningLoop {
  std::vector<uint32_t> vertices;
  uint32_t surface = 0;
  bool small = false;
};

// The loops of one plane and the facets that close them.
struct FlatFill {
  std::vector<size_t> loops;  // indices into the loops given
  // Vertex ids, three a facet, turned as the facets along the loops ask (against their edges).
  std::vector<uint32_t> facets;
  double area = 0;
  size_t loop_edges = 0;  // the loops' edges
  // The last facets close notches (the loops' runs off the plane): per such facet, the facet
  // along its notch's first edge (whose group and fields it takes).
  std::vector<uint32_t> notch_origins;
  size_t rim_edges = 0;              // the edges along the fill's plane region
  size_t flush_edges = 0;            // of those, the ones whose facet lies in the fill's plane
  std::vector<uint32_t> rim_facets;  // the facets along the loops (indices, ascending, once)
};

struct FlatFills {
  std::vector<FlatFill> fills;
  // The surfaces that stay open, and why (each once, ascending); their loops are in no fill.
  std::vector<std::pair<uint32_t, std::string>> open;
};

// The loops grouped by plane: a loop that is not small starts a group, and every loop whose
// corners all lie within `plane_tolerance` of that loop's plane joins it, small ones and other
// surfaces' too, so that a face's holes go with its rim and a face whose loss split its surface
// in two (a shaft's shoulder) joins the two again. Each group is filled by FillPlaneRegion
// (engine/plane_fill.h); small loops in no group are left to the caller. A loop off its plane
// at a few corners only (a facet dropped beside the face) is cut there: each notch is closed by
// its least-area triangulation (engine/least_area_fill.h) and the rest, in one plane, joins its
// group. A surface stays open,
// with the reason, where a loop of it that is not small is not in one plane, or a group holding
// one of its loops is refused: the group's loops bound no region in their plane, or a fill would
// add an edge the surface has or a facet of no area, or cross, overlap or fold onto a facet of
// the surface or of another fill within its box (engine/crossings.h); a group holding a loop of
// a surface that stays open is dropped, and the others of its surfaces stay open too.
// `positions` three floats a vertex, `facets` three vertex ids a facet.
FlatFills FillFlatOpenings(const std::vector<float>& positions, const std::vector<uint32_t>& facets,
                           const std::vector<OpeningLoop>& loops, double plane_tolerance);

}  // namespace femsimp
