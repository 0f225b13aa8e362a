#include "bench/peers/femsimp_modes.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "common/flags.h"
#include "engine/option_flags.h"
#include "engine/option_table.h"
#include "engine/prepare.h"

namespace femsimp::bench {
namespace {

flags::FlagSet ModeFlags(SimplifyOptions* options) {
  flags::FlagSet set("fidelity_table --femsimp-mode");
  for (const OptionSpec& spec : OptionTable())
    if (spec.flag != nullptr) AddOptionFlag(set, spec.path(), options);
  return set;
}

}  // namespace

absl::StatusOr<FemsimpMode> ParseFemsimpMode(const std::string& spec) {
  const size_t eq = spec.find('=');
  if (eq == 0 || eq == std::string::npos)
    return absl::InvalidArgumentError(
        absl::StrCat("--femsimp-mode: '", spec, "' is not of the form NAME=FLAGS"));
  FemsimpMode mode;
  mode.name = spec.substr(0, eq);
  mode.flags = spec.substr(eq + 1);
  const std::vector<std::string> args = absl::StrSplit(mode.flags, ' ', absl::SkipEmpty());
  // Two passes, as femsimp simplify: the first finds the preset, the second starts from it.
  SimplifyOptions first;
  absl::StatusOr<flags::FlagSet::Parsed> parsed = ModeFlags(&first).Parse(args);
  if (!parsed.ok()) return parsed.status();
  mode.options = PresetOptions(first.preset);
  parsed = ModeFlags(&mode.options).Parse(args);
  if (!parsed.ok()) return parsed.status();
  const std::string where = absl::StrCat("--femsimp-mode ", mode.name, ": ");
  if (!parsed->positional.empty())
    return absl::InvalidArgumentError(
        absl::StrCat(where, "unexpected argument '", parsed->positional[0], "'"));
  if (parsed->Given("--tolerance") || parsed->Given("--tolerance-relative"))
    return absl::InvalidArgumentError(
        absl::StrCat(where, "the table sets the tolerance (--tolerances)"));
  mode.threads_given = parsed->Given("--threads");
  if (absl::Status s = ValidateOptions(mode.options); !s.ok())
    return absl::InvalidArgumentError(absl::StrCat(where, s.message()));
  return mode;
}

std::vector<std::string> DefaultFemsimpModes() {
  // Bound only: the fe preset without the volume bound, with minimum angle 0 and normals free
  // up to 180 degrees, so that the tolerance decides; topology and no self-intersection stay (an
  // output that intersects itself cannot be tet-meshed). With the feature lines (sliding along
  // them keeps fewer vertices on CAD parts: fandisk 179 against 195 at 1 %) and without
  // (--feature-angle 180: boundaries only; the organic femur has thousands of 30-degree edges).
  // The `measured` modes keep the tolerance by judging every collapse against the input
  // (--deviation-check measured) instead of carrying a bound along the run.
  const std::string bound = "--max-volume-change 0 --min-angle 0 --max-normal-deviation 180";
  const std::string measured = " --deviation-check measured";
  return {"fe=",
          "fe_quadric=--cost quadric",
          "bound=" + bound,
          "bound_quadric=" + bound + " --cost quadric",
          "bound_nofeatures=" + bound + " --feature-angle 180",
          "fe_measured=" + measured,
          "bound_measured=" + bound + measured};
}

PeerRun RunFemsimp(const RawMesh& input, SimplifyOptions options) {
  PeerRun run;
  // Prepared as femsimp simplify and the server prepare it (repair, spatial renumbering, build):
  // the greedy run's outcome depends on the vertex order, and the table reports what a user
  // gets.
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(input, options.repair);
  if (!prepared.ok()) {
    run.error = prepared.status().ToString();
    return run;
  }
  RunTimer timer(run);
  absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, options);
  timer.Stop();
  if (!result.ok()) {
    run.error = result.status().ToString();
    return run;
  }
  absl::StatusOr<RawMesh> output =
      OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
  if (!output.ok()) {
    run.error = output.status().ToString();
    return run;
  }
  run.output = *std::move(output);
  return run;
}

}  // namespace femsimp::bench
