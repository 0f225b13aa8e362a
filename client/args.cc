#include "client/args.h"

#include <cmath>
#include <functional>
#include <map>
#include <thread>

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace femsimp::cli {
namespace {

constexpr char kExitCodes[] = R"(Exit codes:
  0   success
  1   internal error in the client
  2   usage error: unknown option, missing or non-numeric value, value out of range
  3   input file missing, unreadable or not a supported mesh file
  4   input mesh invalid (non-manifold, degenerate faces, ...)
  5   output mesh or --stats-json file could not be written, or OUT's format cannot hold the
      input's face groups or fields (checked before the run; see --drop-face-data)
  6   the simplification failed
  7   interrupted (local mode)
  8   health: the server answered but is not SERVING
  20+N  remote mode: the server answered with gRPC status code N, e.g.
        21 CANCELLED, 23 INVALID_ARGUMENT, 24 DEADLINE_EXCEEDED, 28 RESOURCE_EXHAUSTED
        (queue full or a server limit), 32 UNIMPLEMENTED, 33 INTERNAL, 34 UNAVAILABLE
        (server not reachable or shutting down)
)";

// The cost and fidelity options, with the engine's defaults.
std::string FidelityUsage() {
  const SimplifyOptions d;
  return absl::StrFormat(
      R"(Cost and fidelity (a bound of 0 is off; fractions also as percentages, e.g. 0.5%%):
  --cost gaussian|quadric   what orders the candidates: discrete Gaussian curvature or the
                            quadric error of the collapse (default %s)
  --tolerance D             guaranteed (Hausdorff) deviation from the input in model units,
                            >= 0 (default %g)
  --tolerance-relative F    the same as a fraction of the bounding-box diagonal, in [0, 1]
                            (default %g); with --tolerance the smaller one applies
  --feature-angle D         dihedral angle in degrees above which an edge is a feature edge,
                            in (0, 180] (default %g; 180: boundaries and group borders only)
  --max-volume-change F     relative change of the enclosed volume, in [0, 1] (default %g)
  --max-centroid-shift F    centroid shift as a fraction of the diagonal, in [0, 1] (default %g)
  --max-field-change F      relative change of each face field's resultant per face group,
                            in (0, 1] (default %g)
)",
      d.cost == CostKind::kQuadric ? "quadric" : "gaussian", d.tolerance, d.tolerance_relative,
      d.feature_angle_deg, d.max_volume_change, d.max_centroid_shift, d.max_field_change);
}

int DefaultThreads() {
  unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

}  // namespace

std::string MainUsage() {
  return absl::StrCat(R"(femsimp: simplify surface triangulations for finite-element meshing.

Usage:
  femsimp simplify IN OUT [options]      simplify locally, or on a server with --server
  femsimp simplify --help                every option of simplify
  femsimp health --server HOST:PORT      ask a server's gRPC health service (health --help)
  femsimp --help                         this text

Mesh formats (by extension): .off .obj .stl .ply
Face groups are kept through .obj and .ply files, face fields through .ply files.

)",
                      kExitCodes);
}

std::string SimplifyUsage() {
  return absl::StrCat(R"(Usage: femsimp simplify IN OUT [options]

Reads the mesh IN, removes vertices by parallel half-edge collapses and writes OUT. Prints one
row per pass and a summary. Options take their value as `--flag VALUE` or `--flag=VALUE`.
Face groups (.obj `g` names, .ply "group") and face fields (.ply float face properties, at
most 3) of IN are carried to OUT; a format of OUT that cannot hold them stops the run before it
starts (exit code 5) unless --drop-face-data is given.

Target (at most one; neither: run until no vertex can be removed or --max-passes):
  --ratio R                 keep R * input vertices, R in [0, 1)
  --target-vertices N       keep N vertices
Engine:
  --threads N               worker threads (contexts) of the native back end, in [1, 1024]
                            (default: the host's cores; remote: the server's default)
  --max-normal-deviation D  max angle in degrees between a new face's normal and the old one,
                            in (0, 180] (default 25)
  --min-angle D             min interior angle in degrees of every new face, in [0, 60)
                            (default 10)
  --candidate-fraction F    share of the lowest-cost vertices tried per pass, in (0, 1]
                            (default 0.9)
  --max-passes N            stop after N passes, in [1, 100000] (default 100)
  --reconsider-every N      retry vertices that failed a criterion every Nth pass (default 3)
  --topology-only           check topology only, no geometric criteria
)",
                      FidelityUsage(), R"(Back end:
  --backend native|cell     shared-memory threads (default) or the emulated Cell BE
  --spes N                  cell: SPE contexts, in [1, 256] (default 1)
  --ls-cache-kib K          cell: software cache size per local store in KiB (default 64, a power of two)
  --spe-threads K           cell: software threads per SPE, in [1, 16] (default 1)
Output:
  --stats-json FILE         write input/output sizes, timings, options, fidelity figures and
                            every pass as JSON
  --quiet                   no per-pass rows, summary only
  --drop-face-data          write OUT without the face groups and fields its format cannot hold
                            (OFF, STL: neither; OBJ: groups only) instead of refusing to run
Remote mode:
  --server HOST:PORT        run the job on a femsimp-server instead of locally
  --deadline SECONDS        give up (and cancel the job) after SECONDS (default: none)
  --label TEXT              a label for the job in the server's list and logs
  --max-attempts N          calls per job, in [1, 100] (default 5): a job that fails with
                            UNAVAILABLE (server or replica gone) or RESOURCE_EXHAUSTED with a
                            retry pushback (queue full) is sent again after a backoff (0.25 s
                            doubling up to 8 s, +-20 %) or the server's pushback; --deadline
                            bounds all attempts together
  --help                    this text

)",
                      kExitCodes);
}

absl::StatusOr<double> ParseDouble(const std::string& flag, const std::string& value) {
  double d;
  if (!absl::SimpleAtod(value, &d) || !std::isfinite(d))
    return absl::InvalidArgumentError(absl::StrCat(flag, ": '", value, "' is not a finite number"));
  return d;
}

absl::StatusOr<double> ParseFraction(const std::string& flag, const std::string& value) {
  if (!absl::EndsWith(value, "%")) return ParseDouble(flag, value);
  absl::StatusOr<double> percent = ParseDouble(flag, value.substr(0, value.size() - 1));
  if (!percent.ok())
    return absl::InvalidArgumentError(
        absl::StrCat(flag, ": '", value, "' is not a finite number or percentage"));
  return *percent / 100.0;
}

absl::StatusOr<long long> ParseInt(const std::string& flag, const std::string& value,
                                   long long min_value, long long max_value) {
  int64_t v;
  if (!absl::SimpleAtoi(value, &v))
    return absl::InvalidArgumentError(absl::StrCat(flag, ": '", value, "' is not an integer"));
  if (v < min_value || v > max_value)
    return absl::InvalidArgumentError(absl::StrCat(flag, " = ", v, " is out of range: must be in [",
                                                   min_value, ", ", max_value, "]"));
  return v;
}

absl::StatusOr<SimplifyArgs> ParseSimplifyArgs(const std::vector<std::string>& args) {
  SimplifyArgs out;
  SimplifyOptions& o = out.options;
  std::vector<std::string> positional;
  bool cell_flag_given = false;
  bool max_attempts_given = false;
  std::string cell_flag;

  // Flags taking a value; each setter parses and stores it.
  using Setter = std::function<absl::Status(const std::string&)>;
  auto dbl = [](const char* flag, double* dst) -> Setter {
    return [flag, dst](const std::string& v) -> absl::Status {
      absl::StatusOr<double> d = ParseDouble(flag, v);
      if (!d.ok()) return d.status();
      *dst = *d;
      return absl::OkStatus();
    };
  };
  auto fraction = [](const char* flag, double* dst) -> Setter {
    return [flag, dst](const std::string& v) -> absl::Status {
      absl::StatusOr<double> d = ParseFraction(flag, v);
      if (!d.ok()) return d.status();
      *dst = *d;
      return absl::OkStatus();
    };
  };
  auto integer = [](const char* flag, int* dst, long long lo, long long hi) -> Setter {
    return [=](const std::string& v) -> absl::Status {
      absl::StatusOr<long long> i = ParseInt(flag, v, lo, hi);
      if (!i.ok()) return i.status();
      *dst = static_cast<int>(*i);
      return absl::OkStatus();
    };
  };
  auto cell = [&](const char* flag, int* dst) -> Setter {
    Setter inner = integer(flag, dst, 0, 1 << 20);
    return [&, flag, inner](const std::string& v) {
      cell_flag_given = true;
      cell_flag = flag;
      return inner(v);
    };
  };
  const std::map<std::string, Setter> with_value = {
      {"--ratio", dbl("--ratio", &o.ratio)},
      {"--target-vertices",
       [&](const std::string& v) -> absl::Status {
         absl::StatusOr<long long> i = ParseInt("--target-vertices", v, 1, 4'000'000'000LL);
         if (!i.ok()) return i.status();
         o.target_vertices = static_cast<uint64_t>(*i);
         return absl::OkStatus();
       }},
      {"--threads",
       [&](const std::string& v) -> absl::Status {
         out.threads_given = true;
         return integer("--threads", &o.threads, 1, 1024)(v);
       }},
      {"--max-normal-deviation", dbl("--max-normal-deviation", &o.max_normal_deviation_deg)},
      {"--min-angle", dbl("--min-angle", &o.min_angle_deg)},
      {"--candidate-fraction", dbl("--candidate-fraction", &o.candidate_fraction)},
      {"--max-passes", integer("--max-passes", &o.max_passes, 1, 100000)},
      {"--reconsider-every", integer("--reconsider-every", &o.reconsider_every, 1, 1000000)},
      {"--cost",
       [&](const std::string& v) -> absl::Status {
         if (v == "gaussian" || v == CostKindName(CostKind::kGaussianCurvature)) {
           o.cost = CostKind::kGaussianCurvature;
         } else if (v == "quadric") {
           o.cost = CostKind::kQuadric;
         } else {
           return absl::InvalidArgumentError(
               absl::StrCat("--cost: '", v, "' is not one of gaussian, quadric"));
         }
         return absl::OkStatus();
       }},
      {"--tolerance", dbl("--tolerance", &o.tolerance)},
      {"--tolerance-relative", fraction("--tolerance-relative", &o.tolerance_relative)},
      {"--feature-angle", dbl("--feature-angle", &o.feature_angle_deg)},
      {"--max-volume-change", fraction("--max-volume-change", &o.max_volume_change)},
      {"--max-centroid-shift", fraction("--max-centroid-shift", &o.max_centroid_shift)},
      {"--max-field-change", fraction("--max-field-change", &o.max_field_change)},
      {"--backend",
       [&](const std::string& v) -> absl::Status {
         if (v == "native") {
           o.backend = Backend::kNative;
         } else if (v == "cell") {
           o.backend = Backend::kCell;
         } else {
           return absl::InvalidArgumentError(
               absl::StrCat("--backend: '", v, "' is not one of native, cell"));
         }
         return absl::OkStatus();
       }},
      {"--spes", cell("--spes", &o.cell.spes)},
      {"--ls-cache-kib", cell("--ls-cache-kib", &o.cell.ls_cache_kib)},
      {"--spe-threads", cell("--spe-threads", &o.cell.spe_threads)},
      {"--stats-json",
       [&](const std::string& v) {
         out.stats_json = v;
         return absl::OkStatus();
       }},
      {"--server",
       [&](const std::string& v) -> absl::Status {
         if (v.empty() || v.find(':') == std::string::npos)
           return absl::InvalidArgumentError(
               absl::StrCat("--server: '", v, "' is not of the form HOST:PORT"));
         out.server = v;
         return absl::OkStatus();
       }},
      {"--deadline",
       [&](const std::string& v) -> absl::Status {
         absl::StatusOr<double> d = ParseDouble("--deadline", v);
         if (!d.ok()) return d.status();
         if (*d <= 0)
           return absl::InvalidArgumentError(
               absl::StrCat("--deadline = ", v, " is out of range: must be > 0 seconds"));
         out.deadline_seconds = *d;
         return absl::OkStatus();
       }},
      {"--label",
       [&](const std::string& v) {
         out.label = v;
         return absl::OkStatus();
       }},
      {"--max-attempts",
       [&](const std::string& v) {
         max_attempts_given = true;
         return integer("--max-attempts", &out.max_attempts, 1, 100)(v);
       }},
  };

  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--topology-only") {
      o.topology_only = true;
      continue;
    }
    if (a == "--quiet") {
      out.quiet = true;
      continue;
    }
    if (a == "--drop-face-data") {
      out.drop_face_data = true;
      continue;
    }
    if (a == "--") {
      for (++i; i < args.size(); ++i) positional.push_back(args[i]);
      break;
    }
    if (absl::StartsWith(a, "--")) {
      std::string name = a, value;
      bool has_value = false;
      if (size_t eq = a.find('='); eq != std::string::npos) {
        name = a.substr(0, eq);
        value = a.substr(eq + 1);
        has_value = true;
      }
      auto it = with_value.find(name);
      if (it == with_value.end()) {
        if (name == "--topology-only" || name == "--quiet" || name == "--drop-face-data")
          return absl::InvalidArgumentError(absl::StrCat(name, " takes no value"));
        return absl::InvalidArgumentError(
            absl::StrCat("unknown option '", name, "' (see femsimp simplify --help)"));
      }
      if (!has_value) {
        if (i + 1 >= args.size())
          return absl::InvalidArgumentError(absl::StrCat(name, " needs a value"));
        value = args[++i];
      }
      if (absl::Status s = it->second(value); !s.ok()) return s;
      continue;
    }
    if (a.size() > 1 && a[0] == '-')
      return absl::InvalidArgumentError(
          absl::StrCat("unknown option '", a, "' (see femsimp simplify --help)"));
    positional.push_back(a);
  }

  if (positional.size() != 2)
    return absl::InvalidArgumentError(absl::StrCat(
        "simplify needs exactly two files, IN and OUT; got ", positional.size(),
        positional.empty() ? "" : absl::StrCat(" (", absl::StrJoin(positional, ", "), ")")));
  out.input = positional[0];
  out.output = positional[1];
  if (cell_flag_given && o.backend != Backend::kCell)
    return absl::InvalidArgumentError(absl::StrCat(cell_flag, " needs --backend cell"));
  if (!out.threads_given) o.threads = DefaultThreads();
  if ((out.deadline_seconds > 0 || !out.label.empty()) && out.server.empty())
    return absl::InvalidArgumentError("--deadline and --label need --server");
  if (max_attempts_given && out.server.empty())
    return absl::InvalidArgumentError("--max-attempts needs --server");
  // Ranges the engine defines (message names the parameter and its range).
  if (absl::Status s = ValidateOptions(o); !s.ok()) return s;
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
  if (sub != "simplify")
    return absl::InvalidArgumentError(
        absl::StrCat("unknown command '", sub, "' (try femsimp --help)"));
  std::vector<std::string> rest(args.begin() + 2, args.end());
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
