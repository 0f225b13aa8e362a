// Loose pieces: open bits of surface beside a part's bodies, as CAD exports carry them (a
// stray facet, a leftover face, construction geometry written with the solid, a facet dangling
// from an edge). One makes the whole mesh an open surface, so it would lose its volume, its mass
// budgets and its FE model; the repair stage removes them and says so (RepairKind::kLoosePiece,
// RepairOptions::loose_piece_share).
//
// A piece is a surface: facets joined through edges of two facets (an edge of three facets or
// more, a seam, joins nothing). A surface is a sheet when it has open edges and the vector area
// of its facets, which is what would close it, is at least half its area (the rule the hole
// fill uses to tell a border from a hole); any other surface is a body: closed, or with holes
// (a facet or a face missing). A sheet is loose when each of its seams keeps two facets without
// it (joined to nothing, or dangling from a body's edge; not one of three walls that meet there)
// and its area is under `max_share` of the bodies' area. A mesh without a body has no loose
// pieces: a sheet part keeps every sheet.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace femsimp {

struct LoosePiece {
  std::vector<uint32_t> faces;  // ascending
  double area = 0;
  double body_area = 0;            // of every body, for the share
  uint32_t attached_edges = 0;     // seams it dangled from (0: joined to nothing)
  std::array<double, 3> centre{};  // area-weighted centroid of its facets
};

// `tri`: three vertex ids per face, in any orientation (a non-orientable surface is a body);
// `edge_of`: per half-edge (3 * face + corner, from that corner to the next) its undirected edge;
// `edge_uses`: per edge, how many half-edges it has. Pieces in order of their first face.
std::vector<LoosePiece> FindLoosePieces(const float* positions, std::span<const uint32_t> tri,
                                        std::span<const uint32_t> edge_of,
                                        std::span<const uint32_t> edge_uses, double max_share);

}  // namespace femsimp
