#include "engine/spatial_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/spatial_key.h"

namespace femsimp {
namespace {

// 10 bits per axis: the 30-bit code and a 32-bit index share one 64-bit sort key; finer cells
// would only reorder elements already within a few cache lines of each other.
constexpr double kCells = double(1 << SpatialKey::kBitsPerAxis);

struct Grid {
  double lo[3] = {0, 0, 0};
  double scale = 0.0;  // cells per model unit
  uint64_t Code(double x, double y, double z) const {
    const double p[3] = {x, y, z};
    uint32_t cell[3];
    for (int a = 0; a < 3; ++a)
      cell[a] = static_cast<uint32_t>(std::clamp((p[a] - lo[a]) * scale, 0.0, kCells - 1.0));
    return Morton3(cell[0], cell[1], cell[2]);
  }
};

Grid GridOf(const std::vector<float>& positions) {
  Grid g;
  double hi[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    g.lo[a] = positions.empty() ? 0.0 : positions[a];
    hi[a] = g.lo[a];
  }
  for (size_t i = 0; i < positions.size(); ++i) {
    const int a = static_cast<int>(i % 3);
    g.lo[a] = std::min(g.lo[a], double(positions[i]));
    hi[a] = std::max(hi[a], double(positions[i]));
  }
  const double extent = std::max({hi[0] - g.lo[0], hi[1] - g.lo[1], hi[2] - g.lo[2]});
  g.scale = extent > 0.0 ? kCells / extent : 0.0;
  return g;
}

// The permutation that sorts `codes` (element i at order[k]), stable in the element index.
std::vector<uint32_t> SortedOrder(const std::vector<uint64_t>& codes) {
  std::vector<uint64_t> keys(codes.size());
  for (size_t i = 0; i < codes.size(); ++i) keys[i] = (codes[i] << 32) | i;
  std::sort(keys.begin(), keys.end());
  std::vector<uint32_t> order(keys.size());
  for (size_t k = 0; k < keys.size(); ++k) order[k] = static_cast<uint32_t>(keys[k]);
  return order;
}

template <class T>
void Permute(std::vector<T>& values, const std::vector<uint32_t>& order, size_t stride) {
  if (values.empty()) return;
  std::vector<T> out(values.size());
  for (size_t k = 0; k < order.size(); ++k)
    std::copy_n(values.begin() + order[k] * stride, stride, out.begin() + k * stride);
  values.swap(out);
}

}  // namespace

std::vector<uint32_t> SortSpatially(RawMesh& raw) {
  const size_t nv = raw.num_vertices(), nf = raw.num_faces();
  if (nv >= (size_t{1} << 32) || nf >= (size_t{1} << 32)) return {};
  if (raw.positions.size() != 3 * nv || raw.triangles.size() != 3 * nf) return {};
  if (!raw.face_groups.empty() && raw.face_groups.size() != nf) return {};
  if (!raw.point_ids.empty() && raw.point_ids.size() != nv) return {};
  for (const FaceField& field : raw.face_fields)
    if (field.values.size() != nf) return {};
  for (uint32_t i : raw.triangles)
    if (i >= nv) return {};
  const Grid grid = GridOf(raw.positions);

  std::vector<uint64_t> codes(nv);
  for (size_t v = 0; v < nv; ++v)
    codes[v] = grid.Code(raw.positions[3 * v], raw.positions[3 * v + 1], raw.positions[3 * v + 2]);
  const std::vector<uint32_t> vertex_order = SortedOrder(codes);
  std::vector<uint32_t> new_id(nv);
  for (size_t k = 0; k < nv; ++k) new_id[vertex_order[k]] = static_cast<uint32_t>(k);
  Permute(raw.positions, vertex_order, 3);
  Permute(raw.point_ids, vertex_order, 1);
  for (uint32_t& i : raw.triangles) i = new_id[i];
  for (uint32_t& v : raw.locked_vertices)
    if (v < nv) v = new_id[v];
  std::sort(raw.locked_vertices.begin(), raw.locked_vertices.end());

  codes.assign(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) c[a] += raw.positions[3 * raw.triangles[3 * f + k] + a];
    codes[f] = grid.Code(c[0] / 3, c[1] / 3, c[2] / 3);
  }
  const std::vector<uint32_t> face_order = SortedOrder(codes);
  Permute(raw.triangles, face_order, 3);
  Permute(raw.face_groups, face_order, 1);
  for (FaceField& field : raw.face_fields) Permute(field.values, face_order, 1);
  return new_id;
}

}  // namespace femsimp
