#include "client/check_cmd.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <optional>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/exit_codes.h"
#include "client/fe_report.h"
#include "client/report.h"
#include "common/escape.h"
#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/prepare.h"
#include "fecheck/fe_check_flags.h"

namespace femsimp::cli {
namespace {

std::atomic<bool> g_interrupted{false};
void OnSigint(int) { g_interrupted.store(true); }

flags::FlagSet CheckFlags(CheckArgs* out) {
  flags::FlagSet set("femsimp check");
  set.Section("Material and units (SI; the defaults are steel's):");
  fecheck::AddFeCheckFlags(set, &out->options);
  set.Section("Output:");
  set.String("--json", "FILE", "write both meshes' figures and their differences as JSON",
             &out->json);
  set.Switch("--quiet", "no progress on stderr", &out->quiet);
  return set;
}

// Reads and repairs one file as `femsimp simplify` does (welds, orientation, ...), so that an
// STL's unshared vertices make a closed surface; the exit code when it fails.
std::optional<RawMesh> ReadSolid(const std::string& path, int* exit_code) {
  absl::StatusOr<RawMesh> raw = ReadMeshFile(path);
  if (!raw.ok()) {
    PrintError("femsimp: cannot read %s: %s\n", path.c_str(),
               EscapeControlCharacters(std::string(raw.status().message())).c_str());
    *exit_code = kExitInputUnreadable;
    return std::nullopt;
  }
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(*std::move(raw), RepairOptions{});
  absl::StatusOr<RawMesh> out =
      prepared.ok() ? OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls)
                    : prepared.status();
  if (!out.ok()) {
    PrintError("femsimp: %s is not a valid mesh: %s\n", path.c_str(),
               std::string(out.status().message()).c_str());
    *exit_code = kExitInputInvalid;
    return std::nullopt;
  }
  if (prepared->report.num_changes() > 0)
    PrintError("femsimp: note: %s repaired before the check: %s\n", path.c_str(),
               prepared->report.Summary().c_str());
  return *std::move(out);
}

}  // namespace

std::string CheckUsage() {
  CheckArgs unused;
  return absl::StrCat(R"(Usage: femsimp check ORIGINAL SIMPLIFIED [options]

Is SIMPLIFIED the same solid as ORIGINAL, mechanically? Both closed surfaces are read (and
repaired as simplify does), tet-meshed with tetgen keeping the surface as given (-pq1.414Y), and
analysed with CalculiX (ccx): quadratic tetrahedra (C3D10), no support (free-free), a frequency
step. Prints for both the volume, mass, centroid and principal moments of inertia (from the
tetrahedra) and the first non-rigid eigenfrequencies (the six rigid-body modes set apart), and
their relative differences. tetgen and ccx are found on the PATH (Debian packages tetgen and
calculix-ccx); they run in a temporary directory that is removed afterwards.

)",
                      CheckFlags(&unused).Help(), R"(
Exit codes: 0 done, 2 usage error, 3 a file cannot be read, 4 a mesh cannot be checked (not a
closed solid, or tetgen refuses it, e.g. for a self-intersection), 5 --json cannot be written,
6 CalculiX failed, 7 interrupted, 9 tetgen or ccx is not on the PATH.
)");
}

absl::StatusOr<CheckArgs> ParseCheckArgs(const std::vector<std::string>& args) {
  CheckArgs out;
  absl::StatusOr<flags::FlagSet::Parsed> parsed = CheckFlags(&out).Parse(args);
  if (!parsed.ok()) return parsed.status();
  out.help = parsed->help;
  if (out.help) return out;
  const std::vector<std::string>& positional = parsed->positional;
  if (positional.size() != 2)
    return absl::InvalidArgumentError(absl::StrCat(
        "check needs exactly two files, ORIGINAL and SIMPLIFIED; got ", positional.size(),
        positional.empty() ? "" : absl::StrCat(" (", absl::StrJoin(positional, ", "), ")")));
  out.original = positional[0];
  out.simplified = positional[1];
  return out;
}

int RunCheck(const CheckArgs& args) {
  // The tools first: without them nothing else is worth reading.
  if (absl::Status tools = fecheck::LocateTools(); !tools.ok()) {
    PrintError("femsimp: %s\n", std::string(tools.message()).c_str());
    return kExitToolMissing;
  }
  int code = kExitOk;
  std::optional<RawMesh> original = ReadSolid(args.original, &code);
  if (!original) return code;
  std::optional<RawMesh> simplified = ReadSolid(args.simplified, &code);
  if (!simplified) return code;

  // Ctrl-C or a SIGTERM kills the running tool (in its own process group, it gets neither).
  std::signal(SIGINT, OnSigint);
  std::signal(SIGTERM, OnSigint);
  absl::StatusOr<fecheck::FeCheckReport> report = fecheck::RunFeCheck(
      *original, *simplified, args.options, TerminalFeControl(args.quiet, &g_interrupted),
      {absl::StrCat("original ", args.original), absl::StrCat("simplified ", args.simplified)});
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (!report.ok()) {
    if (!args.quiet && isatty(fileno(stderr))) std::fputc('\n', stderr);  // end the bar's line
    PrintError("femsimp: FE check failed: %s\n", std::string(report.status().message()).c_str());
    return FeCheckExitCode(report.status());
  }
  const std::array<std::string, 2> paths{args.original, args.simplified};
  std::fputs(FeCheckTable(*report, paths).c_str(), stdout);
  if (!args.json.empty()) {
    if (absl::Status s = WriteTextFile(args.json, FeCheckJson(*report, paths) + "\n"); !s.ok()) {
      PrintError("femsimp: --json: %s\n", std::string(s.message()).c_str());
      return kExitOutputFailed;
    }
  }
  return kExitOk;
}

}  // namespace femsimp::cli
