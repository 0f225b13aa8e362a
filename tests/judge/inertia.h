// Independent principal moments of inertia (unit density), for judging the engine's inertia
// budget and its reported mass properties: integrated with Eigen over the soup's simplices
// mapped from the unit simplex, about the centroid directly (no parallel-axis step), and
// decomposed by Eigen's self-adjoint solver. Shares no code or formula with engine/inertia.
#pragma once

#include <array>

#include "engine/raw_mesh.h"

namespace femsimp::judge {

struct InertiaFigures {
  double measure = 0.0;  // volume (solid) or area (shell)
  std::array<double, 3> centroid{};
  std::array<double, 3> principal_moments{};  // about the centroid, ascending
};

// Of the solid a closed, outward-oriented surface encloses.
InertiaFigures SolidInertia(const RawMesh& mesh);
// Of the surface as a shell of unit thickness (open surfaces).
InertiaFigures ShellInertia(const RawMesh& mesh);

// The largest relative change of a principal moment, same rank against same rank.
double WorstPrincipalMomentChange(const InertiaFigures& before, const InertiaFigures& after);

}  // namespace femsimp::judge
