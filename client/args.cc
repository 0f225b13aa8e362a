#include "client/args.h"

#include <thread>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "common/flags.h"
#include "engine/option_flags.h"
#include "engine/option_table.h"
#include "fecheck/fe_check_flags.h"

namespace femsimp::cli {
namespace {

constexpr char kExitCodes[] = R"(Exit codes:
  0   success
  1   internal error in the client
  2   usage error: unknown option, missing or non-numeric value, value out of range
  3   input file missing, unreadable or not a mesh file the reader can parse (syntax,
      truncation, non-triangle faces, vertex indices beyond the file's vertices, NaN or
      infinite coordinates), in every format alike
  4   input mesh invalid: a defect the repair does not fix (a non-orientable surface, nothing
      left after repair), or, with --repair off, any defect (degenerate, duplicate or flipped
      faces, non-manifold vertices and edges, ...); edges shared by 3 or more faces (the seams
      of an assembly) are kept conforming, simplified only along themselves
  5   output mesh or --stats-json file could not be written, or OUT's format cannot hold the
      input's face groups or fields (checked before the run; see --drop-face-data)
  6   the simplification failed (also: not enough memory)
  7   interrupted (local mode)
  8   health: the server answered but is not SERVING
  9   check, --fe-check: tetgen or ccx (CalculiX) is not on the PATH (Debian packages tetgen,
      calculix-ccx); a mesh the FE check cannot tet-mesh exits with 4, a CalculiX failure with 6
  20+N  remote mode: the server answered with gRPC status code N, e.g.
        21 CANCELLED, 23 INVALID_ARGUMENT, 24 DEADLINE_EXCEEDED, 28 RESOURCE_EXHAUSTED
        (queue full or a server limit), 32 UNIMPLEMENTED, 33 INTERNAL, 34 UNAVAILABLE
        (server not reachable or shutting down)
)";

int DefaultThreads() {
  unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

// The flags of `femsimp simplify`, storing into *out: the engine's from the option table, then
// the client's own.
flags::FlagSet SimplifyFlags(SimplifyArgs* out) {
  flags::FlagSet set("femsimp simplify");
  SimplifyOptions* o = &out->options;
  set.Section("Target (at most one; neither: run until no vertex can be removed or --max-passes):");
  AddOptionFlags(set, "target", o);
  set.Section("Engine:");
  AddOptionFlags(set, "engine", o);
  set.Section("Cost and fidelity (a bound of 0 is off; fractions also as percentages, e.g. 0.5%):");
  AddOptionFlags(set, "fidelity", o);
  set.Section("Back end:");
  AddOptionFlags(set, "backend", o);
  set.Section("Input repair (before the simplification; every change is reported):");
  AddOptionFlags(set, "repair", o);
  set.Switch("--repair-details",
             "list every repair (or, with --repair off, every defect) with its facet and "
             "coordinates; without it the summary lists the first few (--stats-json has them all)",
             &out->repair_details);
  set.Section("Output:");
  set.String("--stats-json", "FILE",
             "write input/output sizes, timings, options, fidelity figures and every pass as JSON",
             &out->stats_json);
  set.Switch("--quiet", "no per-pass rows, summary only", &out->quiet);
  set.Switch("--drop-face-data",
             "write OUT without the face groups and fields its format cannot hold (OFF: "
             "neither; OBJ, MSH, STL: groups only) instead of refusing to run",
             &out->drop_face_data);
  set.Section("FE check (tetgen + CalculiX on IN and OUT after the run, as femsimp check does):");
  set.Switch("--fe-check",
             "tet-mesh IN and OUT, run a free-free modal analysis of both and print their volume, "
             "centroid, principal moments and first eigenfrequencies with the differences "
             "(remote: on the server)",
             &out->fe_check);
  fecheck::AddFeCheckFlags(set, &out->fe_check_options);
  set.Section("Remote mode:");
  set.Value("--server", "HOST:PORT", "run the job on a femsimp-server instead of locally",
            ServerAddressSetter("--server", &out->server));
  set.Number({.name = "--deadline",
              .metavar = "SECONDS",
              .help = "give up (and cancel the job) after SECONDS",
              .range = Range::Above(0),
              .unit = "seconds",
              .default_text = "none"},
             &out->deadline_seconds);
  set.String("--label", "TEXT", "a label for the job in the server's list and logs", &out->label);
  set.Number({.name = "--max-attempts",
              .metavar = "N",
              .help = "calls per job",
              .kind = flags::NumberKind::kInteger,
              .range = Range::Closed(1, 100),
              .default_text = "5",
              .more = ": a job that fails with UNAVAILABLE (server or replica gone) or "
                      "RESOURCE_EXHAUSTED with a retry pushback (queue full) is sent again after "
                      "a backoff (0.25 s doubling up to 8 s, +-20 %) or the server's pushback; "
                      "--deadline bounds all attempts together"},
             &out->max_attempts);
  AddSecurityFlags(set, &out->security);
  return set;
}

std::string OptionsText() {
  std::string s;
  for (const OptionSpec& o : OptionTable()) {
    std::string range = RangeText(o);
    s += flags::HelpEntry(
        o.path(), absl::StrCat(o.help, range.empty() ? "" : "; ", range, "; default ",
                               DefaultText(o), o.flag ? absl::StrCat("; flag ", o.flag) : ""));
  }
  return s;
}

}  // namespace

flags::FlagSet::Setter ServerAddressSetter(std::string flag, std::string* dst) {
  return [flag, dst](const std::string& v) {
    if (v.find(':') == std::string::npos)
      return absl::InvalidArgumentError(
          absl::StrCat(flag, ": '", v, "' is not of the form HOST:PORT"));
    *dst = v;
    return absl::OkStatus();
  };
}

std::string MainUsage() {
  return absl::StrCat(R"(femsimp: simplify surface triangulations for finite-element meshing.

Usage:
  femsimp simplify IN OUT [options]      simplify locally, or on a server with --server
  femsimp simplify --help                every option of simplify
  femsimp check ORIGINAL SIMPLIFIED      FE check: tetgen + CalculiX on both (check --help)
  femsimp health --server HOST:PORT      ask a server's gRPC health service (health --help)
  femsimp options [--markdown]           every engine option: name, flag, range, default
  femsimp --help                         this text

Mesh formats (by extension): .off .obj .stl .ply .msh (gmsh 2.2 and 4.1; written as 4.1)
Face groups are kept through .obj, .ply and .msh files, face fields through .ply files.

)",
                      kExitCodes);
}

std::string SimplifyUsage() {
  SimplifyArgs unused;
  return absl::StrCat(R"(Usage: femsimp simplify IN OUT [options]

Reads the mesh IN, removes vertices by parallel half-edge collapses and writes OUT. Prints one
row per pass and a summary. Options take their value as `--flag VALUE` or `--flag=VALUE`.
Face groups (.obj `g` names, .ply "group", .msh physical groups and their names, the named
solids of an ASCII .stl) and face fields (.ply float face properties, at most 3) of IN are
carried to OUT (an .stl OUT with groups is written ASCII, one solid per group); a format of OUT that
cannot hold them stops the run before it starts (exit code 5) unless --drop-face-data is given.
Of a .msh IN only the 3-node triangles are read; the other elements are counted in a warning.

)",
                      SimplifyFlags(&unused).Help(), "\n", kExitCodes);
}

absl::StatusOr<SimplifyArgs> ParseSimplifyArgs(const std::vector<std::string>& args) {
  // Two passes: the first finds the preset, the second starts from its options, so that an
  // option given explicitly overrides the preset wherever it stands on the line.
  SimplifyArgs first;
  absl::StatusOr<flags::FlagSet::Parsed> parsed = SimplifyFlags(&first).Parse(args);
  if (!parsed.ok()) return parsed.status();
  SimplifyArgs out;
  out.options = PresetOptions(first.options.preset);
  parsed = SimplifyFlags(&out).Parse(args);
  if (!parsed.ok()) return parsed.status();
  const std::vector<std::string>& positional = parsed->positional;
  if (positional.size() != 2)
    return absl::InvalidArgumentError(absl::StrCat(
        "simplify needs exactly two files, IN and OUT; got ", positional.size(),
        positional.empty() ? "" : absl::StrCat(" (", absl::StrJoin(positional, ", "), ")")));
  out.input = positional[0];
  out.output = positional[1];
  if (absl::Status s = CheckCellFlags(*parsed, out.options); !s.ok()) return s;
  out.threads_given = parsed->Given("--threads");
  if (!out.threads_given) out.options.threads = DefaultThreads();
  if ((parsed->Given("--deadline") || parsed->Given("--label")) && out.server.empty())
    return absl::InvalidArgumentError("--deadline and --label need --server");
  if (parsed->Given("--max-attempts") && out.server.empty())
    return absl::InvalidArgumentError("--max-attempts needs --server");
  if (out.security.any() && out.server.empty())
    return absl::InvalidArgumentError("--tls, --tls-*-file and --token-file need --server");
  for (const char* flag : {"--youngs-modulus", "--poisson-ratio", "--density", "--unit-scale",
                           "--modes", "--mesh-size", "--refine-surface", "--fe-threads"})
    if (parsed->Given(flag) && !out.fe_check)
      return absl::InvalidArgumentError(absl::StrCat(flag, " needs --fe-check"));
  if (parsed->Given("--fe-threads") && !out.server.empty())
    return absl::InvalidArgumentError(
        "--fe-threads is for local runs: a server gives CalculiX the job's threads");
  // The rules between options (the engine's words).
  if (absl::Status s = ValidateOptions(out.options); !s.ok()) return s;
  return out;
}

absl::StatusOr<Command> ParseCommandLine(const std::vector<std::string>& args) {
  Command cmd;
  if (args.size() < 2) return absl::InvalidArgumentError("missing command (try femsimp --help)");
  const std::string& sub = args[1];
  if (sub == "--help" || sub == "-h" || sub == "help") {
    cmd.help_text = MainUsage();
    return cmd;
  }
  std::vector<std::string> rest(args.begin() + 2, args.end());
  if (sub == "options") {
    bool markdown = false;
    flags::FlagSet set("femsimp options");
    set.Switch("--markdown", "the README's table", &markdown);
    absl::StatusOr<flags::FlagSet::Parsed> parsed = set.Parse(rest);
    if (!parsed.ok()) return parsed.status();
    if (!parsed->positional.empty())
      return absl::InvalidArgumentError("options takes no arguments besides --markdown");
    cmd.help_text = parsed->help
                        ? absl::StrCat("Usage: femsimp options [--markdown]\n\n", set.Help())
                    : markdown ? OptionsMarkdown()
                               : OptionsText();
    return cmd;
  }
  if (sub == "check") {
    absl::StatusOr<CheckArgs> c = ParseCheckArgs(rest);
    if (!c.ok()) return c.status();
    if (c->help) {
      cmd.help_text = CheckUsage();
      return cmd;
    }
    cmd.kind = Command::kCheck;
    cmd.check = *std::move(c);
    return cmd;
  }
  if (sub != "simplify")
    return absl::InvalidArgumentError(
        absl::StrCat("unknown command '", sub, "' (try femsimp --help)"));
  for (const std::string& a : rest) {
    if (a == "--") break;
    if (a == "--help" || a == "-h") {
      cmd.help_text = SimplifyUsage();
      return cmd;
    }
  }
  absl::StatusOr<SimplifyArgs> s = ParseSimplifyArgs(rest);
  if (!s.ok()) return s.status();
  cmd.kind = Command::kSimplify;
  cmd.simplify = std::move(*s);
  return cmd;
}

}  // namespace femsimp::cli
