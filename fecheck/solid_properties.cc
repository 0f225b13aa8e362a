#include "fecheck/solid_properties.h"

#include "engine/inertia.h"

#include <algorithm>
#include <cmath>

namespace femsimp::fecheck {

SolidProperties MeasureSolid(const TetMesh& mesh, double density) {
  SolidProperties out;
  if (mesh.num_nodes() == 0) return out;
  // Moments about the first node, so that far-off coordinates cost no precision.
  const std::array<double, 3> origin{mesh.nodes[0], mesh.nodes[1], mesh.nodes[2]};
  std::array<double, 3> lo = origin, hi = origin;
  for (size_t n = 0; n < mesh.num_nodes(); ++n)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], mesh.nodes[3 * n + k]);
      hi[k] = std::max(hi[k], mesh.nodes[3 * n + k]);
    }
  out.diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  double volume = 0;
  std::array<double, 3> first{0, 0, 0};
  std::array<std::array<double, 3>, 3> second{};  // integral of x_a x_b
  for (size_t t = 0; t < mesh.num_tets(); ++t) {
    std::array<std::array<double, 3>, 4> p;
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) p[i][k] = mesh.nodes[3 * mesh.tets[4 * t + i] + k] - origin[k];
    double e[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e[i][k] = p[i + 1][k] - p[0][k];
    const double v = (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
                     6;
    std::array<double, 3> sum{0, 0, 0};
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) sum[k] += p[i][k];
    volume += v;
    for (int k = 0; k < 3; ++k) first[k] += v * sum[k] / 4;
    // Over a tetrahedron, the integral of x_a x_b is V/20 (sum_i x_ia x_ib + S_a S_b).
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        double s = sum[a] * sum[b];
        for (int i = 0; i < 4; ++i) s += p[i][a] * p[i][b];
        second[a][b] += v * s / 20;
      }
  }
  out.volume = volume;
  if (volume <= 0) return out;
  std::array<double, 3> c;
  for (int k = 0; k < 3; ++k) {
    c[k] = first[k] / volume;
    out.centroid[k] = origin[k] + c[k];
  }
  // Second moments about the centroid (parallel axes), then the inertia tensor rho (tr(C) I - C).
  std::array<std::array<double, 3>, 3> central, inertia;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) central[a][b] = second[a][b] - volume * c[a] * c[b];
  const double trace = central[0][0] + central[1][1] + central[2][2];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) inertia[a][b] = density * ((a == b ? trace : 0) - central[a][b]);
  const Eigen3 e = Eigen(
      {inertia[0][0], inertia[1][1], inertia[2][2], inertia[0][1], inertia[1][2], inertia[2][0]});
  out.principal_moments = {e.values[0], e.values[1], e.values[2]};
  return out;
}

}  // namespace femsimp::fecheck
