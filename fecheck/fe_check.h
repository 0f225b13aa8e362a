// The FE check (issue 13, item 5): are two closed surfaces — a part and its simplification — the
// same solid mechanically? Each is tet-meshed with tetgen (surface kept as given), its mass
// properties are computed from the tetrahedra, and a free-free modal analysis with CalculiX
// (C3D10) gives its first non-rigid eigenfrequencies; the report holds both and their relative
// differences. No gRPC in here: the CLI (femsimp check, simplify --fe-check) and the server's
// job runner call it on in-memory meshes.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/range.h"
#include "engine/raw_mesh.h"
#include "fecheck/calculix.h"

namespace femsimp::fecheck {

struct FeCheckOptions {
  Material material;        // steel by default
  double unit_scale = 1.0;  // metres per model unit (0.001: the model is in mm)
  int modes = 6;            // elastic eigenfrequencies compared
  // Largest tetrahedron wanted inside both solids, as an edge length relative to the original's
  // bounding-box diagonal (a volume bound for tetgen, the same for both meshes, so that their
  // discretisation errors compare); 0: the surfaces alone decide.
  double mesh_size = 0.05;
  // Keep every surface triangle as a face of the tetrahedra (tetgen -Y); false lets tetgen add
  // points on the surface (the geometry stays), so that a coarse surface meshes as finely as a
  // fine one.
  bool keep_surface = true;
  int threads = 1;  // CalculiX's threads
};

// The options' ranges, shared by ValidateFeCheckOptions, the CLI's flags and the proto's comments.
inline constexpr Range kModulusRange = Range::Above(0);       // Pa
inline constexpr Range kPoissonRange{-1, 0.5, false, false};  // (-1, 0.5)
inline constexpr Range kDensityRange = Range::Above(0);       // kg/m^3
inline constexpr Range kUnitScaleRange = Range::Above(0);     // metres per model unit
inline constexpr Range kModesRange = Range::Closed(1, 50);
inline constexpr Range kMeshSizeRange = Range::Closed(0.005, 1);  // or 0: no bound
inline constexpr Range kThreadsRange = Range::Closed(1, 256);

// InvalidArgument naming the first option out of its range, in the ranges' words.
absl::Status ValidateFeCheckOptions(const FeCheckOptions& options);

// What the check measures of one surface, in SI units.
struct SolidFigures {
  int64_t surface_faces = 0;
  int64_t tetrahedra = 0, nodes = 0;  // the linear tet mesh
  int64_t solver_nodes = 0;           // with the mid-edge nodes of C3D10
  int components = 0;
  double volume = 0.0, mass = 0.0;                   // m^3, kg
  std::array<double, 3> centroid{0, 0, 0};           // m
  std::array<double, 3> principal_moments{0, 0, 0};  // kg m^2, ascending, about the centroid
  double diagonal = 0.0;                             // bounding-box diagonal, m
  std::vector<double> frequencies_hz;                // first non-rigid modes, ascending
  int rigid_modes = 0;                               // set apart (6 per component expected)
  int bodies_meshed_apart = 0;  // touching without shared faces, so not bonded (else 0)
};

struct FeCheckReport {
  FeCheckOptions options;
  SolidFigures original, simplified;
};

// Relative differences (simplified - original) / |original|; the centroid shift as a fraction of
// the original's bounding-box diagonal. Frequencies pairwise, as many as both have.
struct FeDifferences {
  double volume = 0.0, mass = 0.0, centroid_shift = 0.0;
  std::array<double, 3> principal_moments{0, 0, 0};
  std::vector<double> frequencies;
  double worst_moment = 0.0, worst_frequency = 0.0;  // largest magnitude
};
FeDifferences Compare(const SolidFigures& original, const SolidFigures& simplified);

// Progress: a step begins (tet meshing or modal analysis of one mesh), or all are done
// (step == steps).
struct FeStage {
  int step = 0, steps = 0;
  std::string text;  // e.g. "simplified: CalculiX modal analysis, 8,220 nodes"
};
struct FeCheckControl {
  std::function<bool()> cancelled;  // polled while a tool runs; true kills it
  std::function<void(const FeStage&)> on_stage;
};

// The volume bound (model units cubed) of a regular tetrahedron with edge mesh_size * diagonal of
// `original`; 0 when mesh_size is 0.
double MaxTetVolume(const RawMesh& original, double mesh_size);

// Tet-meshes and analyses one surface in its own temporary directory (removed afterwards), with
// tetrahedra no larger than max_tet_volume (model units cubed; 0: no bound).
// Errors name the mesh: InvalidArgument when the surface cannot be checked (not closed, tetgen
// refuses it), Internal when the analysis fails, NotFound when a tool is missing, Cancelled.
absl::StatusOr<SolidFigures> AnalyseSolid(const RawMesh& surface, const std::string& name,
                                          const FeCheckOptions& options, double max_tet_volume,
                                          const FeCheckControl& control = {}, int first_step = 0,
                                          int steps = 2);

// Both surfaces (both checked to be closed before any tool runs), `names` in the messages.
absl::StatusOr<FeCheckReport> RunFeCheck(const RawMesh& original, const RawMesh& simplified,
                                         const FeCheckOptions& options,
                                         const FeCheckControl& control = {},
                                         const std::array<std::string, 2>& names = {"original",
                                                                                    "simplified"});

}  // namespace femsimp::fecheck
