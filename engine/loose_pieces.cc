#include "engine/loose_pieces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "engine/surfaces.h"

namespace femsimp {

std::vector<LoosePiece> FindLoosePieces(const float* positions, std::span<const uint32_t> tri,
                                        std::span<const uint32_t> edge_of,
                                        std::span<const uint32_t> edge_uses, double max_share) {
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  const uint32_t nf = static_cast<uint32_t>(tri.size() / 3);
  if (max_share <= 0 || nf == 0) return {};
  struct Component {
    double area = 0;
    double vector_area[3] = {0, 0, 0};  // with the facets turned as its first one
    double moment[3] = {0, 0, 0};       // area times centroid
    bool open = false;
    bool orientable = true;
    bool detachable = true;  // each of its seams keeps two facets without it
    uint32_t attached = 0;   // its seam edges
  };
  const Surfaces surfaces = FindSurfaces(tri, edge_of, edge_uses);
  const std::vector<uint32_t>& component_of = surfaces.of_facet;
  const std::vector<uint8_t>& parity = surfaces.parity;
  std::vector<Component> of(surfaces.count());
  for (uint32_t id = 0; id < surfaces.count(); ++id) of[id].orientable = surfaces.orientable[id];
  std::vector<std::pair<uint32_t, uint32_t>> on_seams;  // (edge, component) per seam half-edge
  for (uint32_t f = 0; f < nf; ++f) {
    Component& c = of[component_of[f]];
    const float* p[3];
    for (int i = 0; i < 3; ++i) {
      p[i] = positions + 3 * size_t(tri[3 * f + i]);
      const uint32_t e = edge_of[3 * f + i], uses = edge_uses[e];
      c.open |= uses == 1;
      if (uses > 2) on_seams.emplace_back(e, component_of[f]);
    }
    double u[3], w[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = double(p[1][k]) - p[0][k];
      w[k] = double(p[2][k]) - p[0][k];
    }
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                         u[0] * w[1] - u[1] * w[0]};
    const double area = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    c.area += area;
    const double sign = parity[f] ? -0.5 : 0.5;
    for (int k = 0; k < 3; ++k) {
      c.vector_area[k] += sign * n[k];
      c.moment[k] += area * (double(p[0][k]) + p[1][k] + p[2][k]) / 3.0;
    }
  }
  // A surface on a seam comes off where the seam keeps two facets without it (a facet dangling
  // from a solid's edge), not where it is one of three or more walls that meet there.
  std::sort(on_seams.begin(), on_seams.end());
  for (size_t i = 0; i < on_seams.size();) {
    size_t j = i;
    while (j < on_seams.size() && on_seams[j] == on_seams[i]) ++j;
    Component& c = of[on_seams[i].second];
    c.detachable &= edge_uses[on_seams[i].first] - (j - i) == 2;
    ++c.attached;
    i = j;
  }
  // A sheet's facets span it (what would close it is at least half its area); a body's do not:
  // closed, or open where holes are (a facet or a face missing), the hole fill's rule.
  const auto sheet = [](const Component& c) {
    const double closing =
        std::sqrt(c.vector_area[0] * c.vector_area[0] + c.vector_area[1] * c.vector_area[1] +
                  c.vector_area[2] * c.vector_area[2]);
    return c.open && c.orientable && closing >= 0.5 * c.area;
  };
  double body_area = 0;
  for (const Component& c : of)
    if (!sheet(c)) body_area += c.area;
  if (body_area <= 0) return {};

  std::vector<uint32_t> piece_of(of.size(), kNone);
  std::vector<LoosePiece> pieces;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t id = component_of[f];
    const Component& c = of[id];
    if (!sheet(c) || !c.detachable || c.area >= max_share * body_area) continue;
    if (piece_of[id] == kNone) {
      piece_of[id] = static_cast<uint32_t>(pieces.size());
      LoosePiece& p = pieces.emplace_back();
      p.area = c.area;
      p.body_area = body_area;
      p.attached_edges = c.attached;
      for (int k = 0; k < 3; ++k) p.centre[k] = c.area > 0 ? c.moment[k] / c.area : 0.0;
    }
    pieces[piece_of[id]].faces.push_back(f);
  }
  return pieces;
}

}  // namespace femsimp
