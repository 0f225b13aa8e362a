// Second moments and the inertia tensor of a solid or a shell (docs/FIDELITY.md § 5): what the
// inertia budget keeps and what every result reports as principal moments and axes.
#pragma once

#include "engine/vec.h"

namespace femsimp {

// A symmetric 3x3 tensor.
struct Sym3 {
  double xx = 0, yy = 0, zz = 0, xy = 0, yz = 0, zx = 0;

  Sym3& operator+=(const Sym3& o);
  Sym3& operator-=(const Sym3& o);
  double trace() const { return xx + yy + zz; }
};
Sym3 operator+(Sym3 a, const Sym3& b);
Sym3 operator-(Sym3 a, const Sym3& b);
Sym3 operator*(double s, const Sym3& a);
Sym3 Outer(const DVec3& a);                             // a a^T
Sym3 SymmetricProduct(const DVec3& a, const DVec3& b);  // a b^T + b a^T

// The integral of x x^T over a tetrahedron (a, b, c, d) of signed volume `volume`, or over a
// triangle (a, b, c) of area `area`: the moment / 20 (or / 12) of sum(p p^T) + s s^T, s = sum(p).
Sym3 TetrahedronSecondMoment(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d,
                             double volume);
Sym3 TriangleSecondMoment(const DVec3& a, const DVec3& b, const DVec3& c, double area);

// The inertia tensor of unit density whose second moment is j: trace(j) 1 - j.
Sym3 InertiaOf(const Sym3& second);

// Eigenvalues in ascending order and their unit eigenvectors (cyclic Jacobi).
struct Eigen3 {
  double values[3];
  DVec3 axes[3];
};
Eigen3 Eigen(const Sym3& m);

// What a result reports of a mesh's mass (unit density): of the enclosed solid for a closed mesh,
// of the surface (a shell of unit thickness) for an open one.
struct MassSummary {
  bool solid = false;
  double measure = 0.0;  // volume, or area
  DVec3 centroid{0, 0, 0};
  double principal_moments[3] = {0, 0, 0};  // about the centroid, ascending
  DVec3 principal_axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  // The surface's area (an open mesh: the measure). With the volume it gives a solid's mean
  // thickness, MeanThickness().
  double area = 0.0;
};

// 2V/A: a plate's or a wall's thickness (a sphere's: 2/3 of its radius), the scale a tolerance
// is to be compared with where the part is thin; 0 for an open surface or no area.
inline double MeanThickness(const MassSummary& m) {
  return m.solid && m.area > 0.0 ? 2.0 * m.measure / m.area : 0.0;
}

// The largest relative change of a principal moment, same rank against same rank (0 when a
// moment of `before` is 0).
double PrincipalMomentChange(const MassSummary& before, const MassSummary& after);

}  // namespace femsimp
