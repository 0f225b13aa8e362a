#include "fecheck/solid_properties.h"

#include <algorithm>
#include <cmath>

namespace femsimp::fecheck {

std::array<double, 3> SymmetricEigenvalues(const std::array<std::array<double, 3>, 3>& m) {
  std::array<std::array<double, 3>, 3> a = m;
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * scale || off == 0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        // The rotation that zeroes a[p][q] (Numerical Recipes' form, stable for small angles).
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // columns p, q
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // rows p, q
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
      }
  }
  std::array<double, 3> eig{a[0][0], a[1][1], a[2][2]};
  std::sort(eig.begin(), eig.end());
  return eig;
}

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
  out.principal_moments = SymmetricEigenvalues(inertia);
  return out;
}

}  // namespace femsimp::fecheck
