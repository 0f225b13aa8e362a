#include "engine/local_origin.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/coordinate_precision.h"

namespace femsimp {
namespace {

template <typename T>
void BoxOf(const std::vector<T>& xyz, double lo[3], double hi[3]) {
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -std::numeric_limits<double>::infinity();
  }
  for (size_t i = 0; i + 2 < xyz.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(xyz[i + k]));
      hi[k] = std::max(hi[k], double(xyz[i + k]));
    }
}

}  // namespace

std::array<double, 3> LocalOriginOf(const double lo[3], const double hi[3]) {
  const CoordinatePrecision p = PrecisionOfBox(lo, hi);
  if (!(p.diagonal > 0.0) || p.relative_spacing() <= kLocalOriginFrom) return {0.0, 0.0, 0.0};
  std::array<double, 3> origin;
  for (int k = 0; k < 3; ++k) origin[k] = double(static_cast<float>(0.5 * lo[k] + 0.5 * hi[k]));
  return origin;
}

void StoreRelative(const std::vector<double>& xyz, RawMesh* mesh) {
  double lo[3], hi[3];
  BoxOf(xyz, lo, hi);
  mesh->origin = LocalOriginOf(lo, hi);
  mesh->positions.resize(xyz.size());
  for (size_t i = 0; i < xyz.size(); ++i)
    mesh->positions[i] = static_cast<float>(xyz[i] - mesh->origin[i % 3]);
}

void MoveToLocalOrigin(RawMesh* mesh) {
  if (!AtOrigin(mesh->origin)) return;
  double lo[3], hi[3];
  BoxOf(mesh->positions, lo, hi);
  mesh->origin = LocalOriginOf(lo, hi);
  if (AtOrigin(mesh->origin)) return;
  for (size_t i = 0; i < mesh->positions.size(); ++i)
    mesh->positions[i] = static_cast<float>(double(mesh->positions[i]) - mesh->origin[i % 3]);
}

void ChangeOrigin(RawMesh* mesh, const std::array<double, 3>& origin) {
  for (size_t i = 0; i < mesh->positions.size(); ++i)
    mesh->positions[i] =
        static_cast<float>((mesh->origin[i % 3] - origin[i % 3]) + double(mesh->positions[i]));
  mesh->origin = origin;
}

}  // namespace femsimp
