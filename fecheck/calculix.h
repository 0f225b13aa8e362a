// A free-free modal analysis of a tetrahedral mesh with CalculiX: quadratic tetrahedra (C3D10,
// mid-edge nodes added at the edges' midpoints), one isotropic material, no support, a *FREQUENCY
// step; the eigenvalues read from its .dat file and the rigid-body modes set apart.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fecheck/tet_mesh.h"
#include "fecheck/tools.h"

namespace femsimp::fecheck {

struct Material {
  double youngs_modulus = 210e9;  // Pa (steel)
  double poisson_ratio = 0.3;
  double density = 7850;  // kg/m^3
};

struct Modes {
  std::vector<double> elastic_hz;  // the first non-rigid eigenfrequencies, ascending
  int rigid = 0;                   // modes set apart as rigid-body modes
  int nodes = 0;                   // of the quadratic mesh the solver ran on
};

// Writes the CalculiX input deck: nodes (the tetrahedra's and one per edge), C3D10 elements,
// material, and a *FREQUENCY step asking for `eigenvalues` modes. Returns the node count.
int ModalDeck(const TetMesh& mesh, const Material& material, int eigenvalues, std::ostream& out);

// The eigenvalues (omega^2, rad^2/s^2) of the "E I G E N V A L U E   O U T P U T" table of a
// .dat file, in mode order; InvalidArgument when there is no such table.
absl::StatusOr<std::vector<double>> ParseEigenvalues(const std::string& dat);

// Sets the rigid-body modes apart: those below kRigidFraction of the highest frequency found
// (numerically they come out near 1e-6 of it, or as small negative eigenvalues; the elastic
// modes asked for lie within a factor of ~10 of one another).
inline constexpr double kRigidFraction = 1e-4;
Modes SplitRigidModes(const std::vector<double>& eigenvalues, int elastic_wanted);

// Runs ccx on the mesh for six rigid-body modes per component plus `elastic_wanted` modes.
// Internal quoting ccx when it fails or writes no eigenvalues; Cancelled; NotFound (no ccx).
absl::StatusOr<Modes> FreeFreeModes(const TetMesh& mesh, const Material& material,
                                    int elastic_wanted, const ToolRun& run);

}  // namespace femsimp::fecheck
