// The surfaces of a facet soup: facets joined through edges of exactly two facets. An edge of
// three facets or more (a seam) joins nothing, so a facet dangling from a solid's edge, or a
// body written twice sharing an edge with its copy, is a surface of its own. The repair's
// loose-piece and duplicate-body steps read the soup this way.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace femsimp {

struct Surfaces {
  std::vector<uint32_t> of_facet;  // per facet its surface, numbered in order of first facet
  // Per facet: whether it runs against its surface's first facet (the facets need not be
  // oriented yet: two that agree run their common edge opposite ways).
  std::vector<uint8_t> parity;
  std::vector<uint8_t> orientable;  // per surface: no facet's parity conflicts
  uint32_t count() const { return static_cast<uint32_t>(orientable.size()); }
};

// `tri`: three vertex ids per facet; `edge_of`: per half-edge (3 * facet + corner, from that
// corner to the next) its undirected edge; `edge_uses`: per edge, how many half-edges it has.
Surfaces FindSurfaces(std::span<const uint32_t> tri, std::span<const uint32_t> edge_of,
                      std::span<const uint32_t> edge_uses);

}  // namespace femsimp
