#include "client/fe_report.h"

#include <unistd.h>

#include <cstdio>
#include <memory>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/exit_codes.h"
#include "common/json.h"

namespace femsimp::cli {
namespace {

std::string Percent(double relative) { return absl::StrFormat("%+.3f %%", 100 * relative); }

std::string Row(const std::string& what, const std::string& a, const std::string& b,
                const std::string& difference) {
  return absl::StrFormat("  %-28s %-16s %-16s %s\n", what, a, b, difference);
}

std::string Triple(const std::array<double, 3>& v) {
  return absl::StrCat("[", JsonNumber(v[0]), ", ", JsonNumber(v[1]), ", ", JsonNumber(v[2]), "]");
}

std::string List(const std::vector<double>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) absl::StrAppend(&s, i ? ", " : "", JsonNumber(v[i]));
  return s + "]";
}

std::string SolidJson(const fecheck::SolidFigures& f, const std::string& path) {
  return absl::StrCat(
      "{", path.empty() ? "" : absl::StrCat("\"path\": ", JsonString(path), ", "),
      "\"surface_faces\": ", f.surface_faces, ", \"tetrahedra\": ", f.tetrahedra,
      ", \"nodes\": ", f.nodes, ", \"solver_nodes\": ", f.solver_nodes,
      ", \"components\": ", f.components, ", \"bodies_meshed_apart\": ", f.bodies_meshed_apart,
      ", \"volume\": ", JsonNumber(f.volume), ", \"mass\": ", JsonNumber(f.mass),
      ", \"centroid\": ", Triple(f.centroid),
      ", \"principal_moments\": ", Triple(f.principal_moments),
      ", \"diagonal\": ", JsonNumber(f.diagonal), ", \"frequencies_hz\": ", List(f.frequencies_hz),
      ", \"rigid_modes\": ", f.rigid_modes, "}");
}

}  // namespace

std::string FeCheckTable(const fecheck::FeCheckReport& r, const std::array<std::string, 2>& paths) {
  const fecheck::SolidFigures &a = r.original, &b = r.simplified;
  const fecheck::FeDifferences d = fecheck::Compare(a, b);
  const fecheck::Material& m = r.options.material;
  std::string s = absl::StrFormat(
      "FE check: tetgen + CalculiX C3D10, free-free; E = %g Pa, nu = %g, rho = %g kg/m^3, %g m "
      "per model unit\n",
      m.youngs_modulus, m.poisson_ratio, m.density, r.options.unit_scale);
  if (!paths[0].empty()) absl::StrAppend(&s, "  original:   ", paths[0], "\n");
  if (!paths[1].empty()) absl::StrAppend(&s, "  simplified: ", paths[1], "\n");
  auto g = [](double v) { return absl::StrFormat("%.6g", v); };
  absl::StrAppend(&s, Row("", "original", "simplified", "difference"));
  absl::StrAppend(&s, Row("surface triangles", absl::StrCat(a.surface_faces),
                          absl::StrCat(b.surface_faces), ""));
  absl::StrAppend(
      &s, Row("tetrahedra (solver nodes)", absl::StrCat(a.tetrahedra, " (", a.solver_nodes, ")"),
              absl::StrCat(b.tetrahedra, " (", b.solver_nodes, ")"), ""));
  absl::StrAppend(&s, Row("volume [m^3]", g(a.volume), g(b.volume), Percent(d.volume)));
  absl::StrAppend(&s, Row("mass [kg]", g(a.mass), g(b.mass), Percent(d.mass)));
  for (int k = 0; k < 3; ++k)
    absl::StrAppend(
        &s, Row(absl::StrCat("centroid ", std::string(1, "xyz"[k]), " [m]"), g(a.centroid[k]),
                g(b.centroid[k]),
                k == 2 ? absl::StrFormat("shift %.3f %% of the diagonal", 100 * d.centroid_shift)
                       : ""));
  for (int k = 0; k < 3; ++k)
    absl::StrAppend(
        &s, Row(absl::StrCat("principal moment ", k + 1, " [kg m^2]"), g(a.principal_moments[k]),
                g(b.principal_moments[k]), Percent(d.principal_moments[k])));
  const size_t modes = std::max(a.frequencies_hz.size(), b.frequencies_hz.size());
  for (size_t i = 0; i < modes; ++i) {
    auto hz = [&](const fecheck::SolidFigures& f) {
      return i < f.frequencies_hz.size() ? g(f.frequencies_hz[i]) : std::string("-");
    };
    absl::StrAppend(&s, Row(absl::StrCat("frequency ", i + 1, " [Hz]"), hz(a), hz(b),
                            i < d.frequencies.size() ? Percent(d.frequencies[i]) : ""));
  }
  absl::StrAppend(&s, Row("rigid-body modes set apart", absl::StrCat(a.rigid_modes),
                          absl::StrCat(b.rigid_modes), ""));
  for (const fecheck::SolidFigures* f : {&a, &b})
    if (f->rigid_modes != 6 * f->components)
      absl::StrAppend(&s, "  note: the ", f == &a ? "original" : "simplified", " mesh has ",
                      f->rigid_modes, " near-zero modes for ", f->components,
                      " part(s), 6 each expected: a part may hang by a thread\n");
  for (const fecheck::SolidFigures* f : {&a, &b})
    if (f->bodies_meshed_apart > 0)
      absl::StrAppend(&s, "  note: the ", f == &a ? "original" : "simplified", " surface's ",
                      f->bodies_meshed_apart,
                      " bodies touch without sharing faces: each was tet-meshed on its own, so "
                      "they are not bonded (their contacts carry no load)\n");
  // With the surfaces kept (tetgen -Y), a coarse surface makes a coarse tet mesh, whose
  // discretisation error (stiffer: higher frequencies) adds to the geometric difference.
  const double ratio =
      static_cast<double>(std::max(a.tetrahedra, b.tetrahedra)) /
      static_cast<double>(std::max<int64_t>(1, std::min(a.tetrahedra, b.tetrahedra)));
  if (r.options.keep_surface && ratio > 2)
    absl::StrAppend(&s, absl::StrFormat("  note: the tet meshes differ %.1fx in size, so the "
                                        "frequency differences include discretisation error; "
                                        "--refine-surface meshes both alike\n",
                                        ratio));
  absl::StrAppend(
      &s, absl::StrFormat("  worst: volume %.3f %%, principal moments %.3f %%, "
                          "frequencies %.3f %%\n",
                          100 * std::abs(d.volume), 100 * d.worst_moment, 100 * d.worst_frequency));
  return s;
}

std::string FeCheckJson(const fecheck::FeCheckReport& r, const std::array<std::string, 2>& paths,
                        int indent) {
  const fecheck::FeDifferences d = fecheck::Compare(r.original, r.simplified);
  const fecheck::Material& m = r.options.material;
  const std::string pad(indent + 2, ' ');
  return absl::StrCat(
      "{\n", pad, "\"material\": {\"youngs_modulus\": ", JsonNumber(m.youngs_modulus),
      ", \"poisson_ratio\": ", JsonNumber(m.poisson_ratio),
      ", \"density\": ", JsonNumber(m.density), "},\n", pad,
      "\"mesh_size\": ", JsonNumber(r.options.mesh_size), ",\n", pad,
      "\"keep_surface\": ", r.options.keep_surface ? "true" : "false", ",\n", pad,
      "\"unit_scale\": ", JsonNumber(r.options.unit_scale), ",\n", pad,
      "\"modes\": ", r.options.modes, ",\n", pad, "\"original\": ", SolidJson(r.original, paths[0]),
      ",\n", pad, "\"simplified\": ", SolidJson(r.simplified, paths[1]), ",\n", pad,
      "\"differences\": {\"volume\": ", JsonNumber(d.volume), ", \"mass\": ", JsonNumber(d.mass),
      ", \"centroid_shift\": ", JsonNumber(d.centroid_shift),
      ", \"principal_moments\": ", Triple(d.principal_moments),
      ", \"frequencies\": ", List(d.frequencies),
      ", \"worst_moment\": ", JsonNumber(d.worst_moment),
      ", \"worst_frequency\": ", JsonNumber(d.worst_frequency), "}\n", std::string(indent, ' '),
      "}");
}

fecheck::FeCheckControl TerminalFeControl(bool quiet, const std::atomic<bool>* interrupted) {
  fecheck::FeCheckControl control;
  if (interrupted != nullptr)
    control.cancelled = [interrupted] { return interrupted->load(std::memory_order_relaxed); };
  if (quiet) return control;
  const bool tty = isatty(fileno(stderr));
  control.on_stage = [tty](const fecheck::FeStage& s) {
    constexpr int kWidth = 20;
    const int filled = s.steps > 0 ? kWidth * s.step / s.steps : 0;
    if (tty) {
      std::fprintf(stderr, "\r[%s%s] %d/%d %s\x1b[K%s", std::string(filled, '#').c_str(),
                   std::string(kWidth - filled, '.').c_str(), s.step, s.steps, s.text.c_str(),
                   s.step == s.steps ? "\n" : "");
    } else {
      std::fprintf(stderr, "FE check %d/%d: %s\n", s.step, s.steps, s.text.c_str());
    }
    std::fflush(stderr);
  };
  return control;
}

int FeCheckExitCode(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kOk:
      return kExitOk;
    case absl::StatusCode::kNotFound:
      return kExitToolMissing;
    case absl::StatusCode::kInvalidArgument:
      return kExitInputInvalid;
    case absl::StatusCode::kCancelled:
      return kExitCancelled;
    default:
      return kExitEngineFailed;
  }
}

}  // namespace femsimp::cli
