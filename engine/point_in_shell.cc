#include "engine/point_in_shell.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace femsimp {
namespace {

// The sign of edge (u, v)'s test at q in the (y, z) plane, for the point moved by (ε, ε²):
// computed with the edge from its lower vertex id, so that both facets of an edge agree.
int EdgeSide(uint32_t iu, const DVec3& u, uint32_t iv, const DVec3& v, double qy, double qz) {
  const bool swapped = iv < iu;
  const DVec3& a = swapped ? v : u;
  const DVec3& b = swapped ? u : v;
  const double dy = b.y - a.y, dz = b.z - a.z;
  const double e = dy * (qz - a.z) - dz * (qy - a.y);
  int side = e > 0 ? 1 : e < 0 ? -1 : dz != 0 ? (dz < 0 ? 1 : -1) : dy > 0 ? 1 : dy < 0 ? -1 : 0;
  return swapped ? -side : side;
}

}  // namespace

PointInShell::PointInShell(const float* positions, std::vector<uint32_t> corners)
    : positions_(positions), corners_(std::move(corners)) {
  const size_t facets = corners_.size() / 3;
  if (facets == 0) return;
  lo_ = hi_ = {Position(corners_[0]).y, Position(corners_[0]).z};
  for (uint32_t c : corners_) {
    const DVec3 p = Position(c);
    lo_ = {std::min(lo_[0], p.y), std::min(lo_[1], p.z)};
    hi_ = {std::max(hi_[0], p.y), std::max(hi_[1], p.z)};
  }
  cells_ = std::clamp(int(std::sqrt(double(facets)) / 2), 1, 1024);
  // Two passes over the facets' cell ranges: count, then fill.
  std::vector<uint32_t> count(size_t(cells_) * cells_ + 1, 0);
  const auto for_cells = [&](size_t f, auto&& visit) {
    double ylo = hi_[0], yhi = lo_[0], zlo = hi_[1], zhi = lo_[1];
    for (int k = 0; k < 3; ++k) {
      const DVec3 p = Position(corners_[3 * f + k]);
      ylo = std::min(ylo, p.y), yhi = std::max(yhi, p.y);
      zlo = std::min(zlo, p.z), zhi = std::max(zhi, p.z);
    }
    for (int y = Cell(ylo, 0); y <= Cell(yhi, 0); ++y)
      for (int z = Cell(zlo, 1); z <= Cell(zhi, 1); ++z) visit(size_t(y) * cells_ + z);
  };
  for (size_t f = 0; f < facets; ++f) for_cells(f, [&](size_t cell) { ++count[cell + 1]; });
  for (size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  cell_begin_ = count;
  cell_facets_.resize(count.back());
  for (size_t f = 0; f < facets; ++f)
    for_cells(f, [&](size_t cell) { cell_facets_[count[cell]++] = uint32_t(f); });
}

DVec3 PointInShell::Position(uint32_t v) const {
  const float* p = &positions_[3 * size_t(v)];
  return {p[0], p[1], p[2]};
}

int PointInShell::Cell(double x, int axis) const {
  // NaN (an overflowing extent) and out-of-range values are clamped before the conversion.
  const double t = (x - lo_[axis]) / (hi_[axis] - lo_[axis]) * cells_;
  return t >= 0 ? (t < cells_ ? int(t) : cells_ - 1) : 0;
}

int PointInShell::Winding(const DVec3& p) const {
  if (corners_.empty() || p.y < lo_[0] || p.y > hi_[0] || p.z < lo_[1] || p.z > hi_[1]) return 0;
  const size_t cell = size_t(Cell(p.y, 0)) * cells_ + Cell(p.z, 1);
  int winding = 0;
  for (uint32_t i = cell_begin_[cell]; i < cell_begin_[cell + 1]; ++i) {
    const uint32_t* t = &corners_[3 * size_t(cell_facets_[i])];
    const DVec3 a = Position(t[0]), b = Position(t[1]), c = Position(t[2]);
    const int s0 = EdgeSide(t[0], a, t[1], b, p.y, p.z);
    const int s1 = EdgeSide(t[1], b, t[2], c, p.y, p.z);
    const int s2 = EdgeSide(t[2], c, t[0], a, p.y, p.z);
    if (s0 == 0 || s0 != s1 || s1 != s2) continue;  // not over the facet (or no area there)
    // Where the ray meets the facet's plane: beyond p counts, with the facet's facing.
    const DVec3 n = Cross(b - a, c - a);
    if (n.x == 0) continue;
    const double x = a.x - (n.y * (p.y - a.y) + n.z * (p.z - a.z)) / n.x;
    if (x > p.x) winding += s0;
  }
  return winding;
}

}  // namespace femsimp
