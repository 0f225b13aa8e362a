#include "tests/judge/inertia.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace femsimp::judge {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Vector3d Corner(const RawMesh& m, size_t f, int i, const Vector3d& shift) {
  const uint32_t v = m.triangles[3 * f + i];
  return Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]) - shift;
}

// Measure, first and second moment of every simplex, with positions taken relative to `shift`.
struct Moments {
  double measure = 0.0;
  Vector3d first = Vector3d::Zero();
  Matrix3d second = Matrix3d::Zero();
};

// The tetrahedron (0, a, b, c) is A u over the unit simplex u >= 0, sum u <= 1, A = [a b c]:
// its moments are det A times those of the unit simplex: 1/6, 1/24 each, (1 + [i == j]) / 120.
Moments SolidMoments(const RawMesh& m, const Vector3d& shift) {
  Matrix3d unit_second;
  unit_second.setConstant(1.0 / 120.0);
  unit_second.diagonal().setConstant(2.0 / 120.0);
  Moments s;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    Matrix3d a;
    a << Corner(m, f, 0, shift), Corner(m, f, 1, shift), Corner(m, f, 2, shift);
    const double det = a.determinant();
    s.measure += det / 6.0;
    s.first += det * a * Vector3d::Constant(1.0 / 24.0);
    s.second += det * a * unit_second * a.transpose();
  }
  return s;
}

// The triangle p + E u over the unit triangle, E = [q - p, r - p]: twice its area times the unit
// triangle's moments 1/2, 1/6 each, and (1 + [i == j]) / 24.
Moments ShellMoments(const RawMesh& m, const Vector3d& shift) {
  Eigen::Matrix2d unit_second;
  unit_second << 2.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0, 2.0 / 24.0;
  Moments s;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const Vector3d p = Corner(m, f, 0, shift);
    Eigen::Matrix<double, 3, 2> e;
    e << Corner(m, f, 1, shift) - p, Corner(m, f, 2, shift) - p;
    const double jacobian = e.col(0).cross(e.col(1)).norm();
    const Vector3d mean_offset = e * Eigen::Vector2d::Constant(1.0 / 6.0);
    s.measure += jacobian / 2.0;
    s.first += jacobian * (p / 2.0 + mean_offset);
    s.second += jacobian * (p * p.transpose() / 2.0 + p * mean_offset.transpose() +
                            mean_offset * p.transpose() + e * unit_second * e.transpose());
  }
  return s;
}

InertiaFigures Figures(const RawMesh& m, Moments (*moments)(const RawMesh&, const Vector3d&)) {
  // The centroid first, then every moment about it.
  const Moments around_origin = moments(m, Vector3d::Zero());
  InertiaFigures out;
  out.measure = around_origin.measure;
  if (out.measure == 0.0) return out;
  const Vector3d centroid = around_origin.first / around_origin.measure;
  const Moments central = moments(m, centroid);
  const Matrix3d inertia = central.second.trace() * Matrix3d::Identity() - central.second;
  const Eigen::SelfAdjointEigenSolver<Matrix3d> solver(inertia);
  for (int k = 0; k < 3; ++k) {
    out.centroid[k] = centroid[k];
    out.principal_moments[k] = solver.eigenvalues()[k];
  }
  return out;
}

}  // namespace

InertiaFigures SolidInertia(const RawMesh& mesh) { return Figures(mesh, SolidMoments); }
InertiaFigures ShellInertia(const RawMesh& mesh) { return Figures(mesh, ShellMoments); }

double WorstPrincipalMomentChange(const InertiaFigures& before, const InertiaFigures& after) {
  double worst = 0.0;
  for (int k = 0; k < 3; ++k)
    if (before.principal_moments[k] != 0.0)
      worst = std::max(worst, std::abs(after.principal_moments[k] - before.principal_moments[k]) /
                                  std::abs(before.principal_moments[k]));
  return worst;
}

}  // namespace femsimp::judge
