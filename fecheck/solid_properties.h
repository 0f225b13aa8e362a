// Mass properties of a tetrahedral mesh, computed from its tetrahedra alone (not by the solver):
// volume, centroid, inertia tensor about the centroid and its principal moments.
#pragma once

#include <array>

#include "fecheck/tet_mesh.h"

namespace femsimp::fecheck {

struct SolidProperties {
  double volume = 0.0;                               // m^3
  std::array<double, 3> centroid{0, 0, 0};           // m
  std::array<double, 3> principal_moments{0, 0, 0};  // kg m^2 at the density given, ascending
  double diagonal = 0.0;                             // bounding-box diagonal of the nodes, m
};

SolidProperties MeasureSolid(const TetMesh& mesh, double density);

}  // namespace femsimp::fecheck
