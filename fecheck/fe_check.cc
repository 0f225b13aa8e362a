#include "fecheck/fe_check.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/flags.h"
#include "fecheck/solid_properties.h"
#include "fecheck/temp_dir.h"

namespace femsimp::fecheck {
namespace {

absl::Status Named(const std::string& name, const absl::Status& s) {
  return absl::Status(s.code(), absl::StrCat(name, ": ", s.message()));
}

double Relative(double original, double simplified) {
  return original == 0 ? 0.0 : (simplified - original) / std::abs(original);
}

// 12345 -> "12,345".
std::string Thousands(int64_t n) {
  std::string digits = absl::StrCat(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace

absl::Status ValidateFeCheckOptions(const FeCheckOptions& o) {
  const struct {
    const char* name;
    double value;
    Range range;
    const char* unit;
    const char* zero_means;  // non-empty: 0 is allowed besides the range
  } checks[] = {{"youngs_modulus", o.material.youngs_modulus, kModulusRange, "Pa", ""},
                {"poisson_ratio", o.material.poisson_ratio, kPoissonRange, "", ""},
                {"density", o.material.density, kDensityRange, "kg/m^3", ""},
                {"unit_scale", o.unit_scale, kUnitScaleRange, "metres per model unit", ""},
                {"modes", static_cast<double>(o.modes), kModesRange, "", ""},
                {"mesh_size", o.mesh_size, kMeshSizeRange, "", "no bound"},
                {"threads", static_cast<double>(o.threads), kThreadsRange, "", ""}};
  for (const auto& c : checks)
    if (!c.range.Contains(c.value) && !(c.zero_means[0] != '\0' && c.value == 0))
      return flags::OutOfRange(c.name, FormatNumber(c.value), c.range, c.unit, c.zero_means);
  return absl::OkStatus();
}

FeDifferences Compare(const SolidFigures& a, const SolidFigures& b) {
  FeDifferences d;
  d.volume = Relative(a.volume, b.volume);
  d.mass = Relative(a.mass, b.mass);
  d.centroid_shift = a.diagonal > 0
                         ? std::hypot(b.centroid[0] - a.centroid[0], b.centroid[1] - a.centroid[1],
                                      b.centroid[2] - a.centroid[2]) /
                               a.diagonal
                         : 0.0;
  for (int k = 0; k < 3; ++k) {
    d.principal_moments[k] = Relative(a.principal_moments[k], b.principal_moments[k]);
    d.worst_moment = std::max(d.worst_moment, std::abs(d.principal_moments[k]));
  }
  const size_t n = std::min(a.frequencies_hz.size(), b.frequencies_hz.size());
  for (size_t i = 0; i < n; ++i) {
    d.frequencies.push_back(Relative(a.frequencies_hz[i], b.frequencies_hz[i]));
    d.worst_frequency = std::max(d.worst_frequency, std::abs(d.frequencies.back()));
  }
  return d;
}

double MaxTetVolume(const RawMesh& original, double mesh_size) {
  if (mesh_size <= 0 || original.num_vertices() == 0) return 0.0;
  std::array<double, 3> lo{original.positions[0], original.positions[1], original.positions[2]};
  std::array<double, 3> hi = lo;
  for (size_t i = 0; i < original.positions.size(); ++i) {
    lo[i % 3] = std::min<double>(lo[i % 3], original.positions[i]);
    hi[i % 3] = std::max<double>(hi[i % 3], original.positions[i]);
  }
  const double edge = mesh_size * std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  return edge * edge * edge / (6 * std::sqrt(2.0));
}

absl::StatusOr<SolidFigures> AnalyseSolid(const RawMesh& surface, const std::string& name,
                                          const FeCheckOptions& options, double max_tet_volume,
                                          const FeCheckControl& control, int first_step,
                                          int steps) {
  if (absl::Status s = ValidateFeCheckOptions(options); !s.ok()) return s;
  if (absl::Status s = CheckClosedSolid(surface); !s.ok()) return Named(name, s);
  const auto stage = [&](int step, std::string text) {
    if (control.on_stage)
      control.on_stage({first_step + step, steps, absl::StrCat(name, ": ", text)});
  };
  absl::StatusOr<TempDir> dir = TempDir::Create();
  if (!dir.ok()) return Named(name, dir.status());
  const ToolRun run{.dir = dir->path(), .cancelled = control.cancelled, .threads = options.threads};

  stage(0, absl::StrCat("tetgen on ", Thousands(surface.num_faces()), " triangles"));
  absl::StatusOr<TetMesh> tets =
      Tetrahedralise(surface, options.unit_scale, max_tet_volume, options.keep_surface, run);
  if (!tets.ok()) return Named(name, tets.status());
  SolidFigures f;
  f.surface_faces = static_cast<int64_t>(surface.num_faces());
  f.tetrahedra = static_cast<int64_t>(tets->num_tets());
  f.nodes = static_cast<int64_t>(tets->num_nodes());
  f.components = tets->components;
  f.bodies_meshed_apart = tets->bodies_meshed_apart;
  const SolidProperties solid = MeasureSolid(*tets, options.material.density);
  f.volume = solid.volume;
  f.mass = options.material.density * solid.volume;
  f.centroid = solid.centroid;  // tetgen ran on positions relative to the surface's origin
  for (int k = 0; k < 3; ++k) f.centroid[k] += surface.origin[k] * options.unit_scale;
  f.principal_moments = solid.principal_moments;
  f.diagonal = solid.diagonal;

  stage(1, absl::StrCat("CalculiX modal analysis, ", Thousands(f.tetrahedra), " C3D10"));
  absl::StatusOr<Modes> modes = FreeFreeModes(*tets, options.material, options.modes, run);
  if (!modes.ok()) return Named(name, modes.status());
  f.frequencies_hz = modes->elastic_hz;
  f.rigid_modes = modes->rigid;
  f.solver_nodes = modes->nodes;
  return f;
}

absl::StatusOr<FeCheckReport> RunFeCheck(const RawMesh& original, const RawMesh& simplified,
                                         const FeCheckOptions& options,
                                         const FeCheckControl& control,
                                         const std::array<std::string, 2>& names) {
  if (absl::Status s = ValidateFeCheckOptions(options); !s.ok()) return s;
  if (absl::Status s = LocateTools(); !s.ok()) return s;
  // Both surfaces before any tool runs: a bad second one should not cost the first's analysis.
  if (absl::Status s = CheckClosedSolid(original); !s.ok()) return Named(names[0], s);
  if (absl::Status s = CheckClosedSolid(simplified); !s.ok()) return Named(names[1], s);
  FeCheckReport report;
  report.options = options;
  const double max_tet_volume = MaxTetVolume(original, options.mesh_size);
  absl::StatusOr<SolidFigures> a =
      AnalyseSolid(original, names[0], options, max_tet_volume, control, 0, 4);
  if (!a.ok()) return a.status();
  report.original = *std::move(a);
  absl::StatusOr<SolidFigures> b =
      AnalyseSolid(simplified, names[1], options, max_tet_volume, control, 2, 4);
  if (!b.ok()) return b.status();
  report.simplified = *std::move(b);
  if (control.on_stage) control.on_stage({4, 4, "done"});
  return report;
}

}  // namespace femsimp::fecheck
