#include "engine/option_table.h"

#include <cmath>
#include <limits>
#include <type_traits>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "common/flags.h"

namespace femsimp {
namespace {

using T = OptionType;
using S = SimplifyOptions;
using C = CellOptions;
using R = RepairOptions;

// An enum row's value is the choice's index, which must be the engine enum's value.
static_assert(static_cast<int>(RepairMode::kOff) == 0 && static_cast<int>(RepairMode::kOn) == 1);
static_assert(static_cast<int>(HoleFill::kSmall) == 0 && static_cast<int>(HoleFill::kPlanar) == 1 &&
              static_cast<int>(HoleFill::kNone) == 2);

// The defaults are SimplifyOptions' own (simplify.h): the table reads them.
std::vector<OptionSpec> MakeTable() {
  // clang-format off
  std::vector<OptionSpec> table = {
      // First: the others' defaults depend on it (PresetOptions).
      {.name = "preset", .flag = "--preset", .section = "target", .type = T::kEnum,
       .help = "fe: safe finite-element defaults (bounded deviation and volume, no "
               "self-intersections, slivers may only improve); paper: the paper's criteria "
               "alone, for its benchmark; options given explicitly override the preset's",
       .choices = {{"fe", "fe"}, {"paper", "paper"}}, .field = &S::preset},
      {.name = "ratio", .flag = "--ratio", .metavar = "R", .section = "target",
       .range = Range::ClosedOpen(0, 1), .zero_means = "none", .help = "keep R * input vertices",
       .field = &S::ratio},
      {.name = "target_vertices", .flag = "--target-vertices", .metavar = "N", .section = "target",
       .type = T::kCount, .range = Range::Closed(1, 4e9), .zero_means = "none",
       .help = "keep N vertices", .field = &S::target_vertices},
      {.name = "threads", .flag = "--threads", .metavar = "N", .section = "engine", .type = T::kInt,
       .range = Range::Closed(1, 1024),
       .default_note = "the host's cores; remote: the server's default",
       .help = "worker threads (contexts) of the native back end", .field = &S::threads},
      {.name = "max_normal_deviation_deg", .flag = "--max-normal-deviation", .metavar = "D",
       .section = "engine", .range = Range::OpenClosed(0, 180), .unit = "degrees",
       .help = "max angle between a new face's normal and the old one",
       .field = &S::max_normal_deviation_deg},
      {.name = "min_angle_deg", .flag = "--min-angle", .metavar = "D", .section = "engine",
       .range = Range::ClosedOpen(0, 60), .unit = "degrees",
       .help = "min interior angle of every new face (0: off)", .field = &S::min_angle_deg},
      {.name = "candidate_fraction", .flag = "--candidate-fraction", .metavar = "F",
       .section = "engine", .range = Range::OpenClosed(0, 1),
       .help = "share of the lowest-cost vertices tried per pass", .field = &S::candidate_fraction},
      {.name = "max_passes", .flag = "--max-passes", .metavar = "N", .section = "engine",
       .type = T::kInt, .range = Range::Closed(1, 100000), .help = "stop after N passes",
       .field = &S::max_passes},
      {.name = "reconsider_every", .flag = "--reconsider-every", .metavar = "N",
       .section = "engine", .type = T::kInt, .range = Range::Closed(1, 1000000),
       .help = "retry vertices that failed a criterion every Nth pass",
       .field = &S::reconsider_every},
      {.name = "periodic_retry", .flag = "--periodic-retry", .section = "engine",
       .type = T::kBool,
       .help = "a vertex that failed a criterion waits for the next --reconsider-every pass even "
               "when a collapse has changed its fan (the paper's form); by default it is a "
               "candidate again the next pass, and only criteria that look beyond its fan "
               "(topology, budgets, intersections) are retried every Nth pass",
       .field = &S::periodic_retry},
      {.name = "schedule", .flag = "--schedule", .section = "engine", .type = T::kEnum,
       .help = "deterministic: collapses run in rounds of non-interacting neighbourhoods, so the "
               "output is the same for any thread or SPE count; free: the paper's lock races "
               "(outputs vary between runs with more than one context)",
       .choices = {{"deterministic", "deterministic"}, {"free", "free"}}, .field = &S::schedule},
      {.name = "topology_only", .flag = "--topology-only", .section = "engine", .type = T::kBool,
       .help = "check topology only, no geometric criteria", .field = &S::topology_only},
      {.name = "strict_min_angle", .flag = "--strict-min-angle", .section = "engine",
       .type = T::kBool,
       .help = "every new angle must reach --min-angle (the paper's form); by default a new "
               "triangle may also be no worse than the worst it replaces, so slivers improve",
       .field = &S::strict_min_angle},
      {.name = "allow_self_intersections", .flag = "--allow-self-intersections",
       .section = "fidelity", .type = T::kBool,
       .help = "do not check new triangles against the mesh (faster; output may self-intersect)",
       .field = &S::allow_self_intersections},
      {.name = "cost", .flag = "--cost", .section = "fidelity", .type = T::kEnum,
       .help = "what orders the candidates: discrete Gaussian curvature, the quadric error of "
               "the collapse, or the deviation bound already spent around the vertex (spends the "
               "tolerance evenly; without a tolerance, the Gaussian curvature)",
       .choices = {{"gaussian_curvature", "gaussian"}, {"quadric", "quadric"},
                   {"deviation", "deviation"}},
       .field = &S::cost},
      {.name = "placement", .flag = "--placement", .section = "fidelity", .type = T::kEnum,
       .help = "endpoint: the paper's half-edge collapse (a vertex moves onto a neighbour); "
               "optimal: where a mass budget (or the measured tolerance) refuses it and both "
               "ends of the edge are free to move (no boundary, seam or group border; no "
               "feature line, or with the measured tolerance both ends on one crease), merge "
               "them at the point nearest the old faces that keeps the volume, or else at "
               "another point that keeps it, nearer the kept end or at the edge's midpoint, if "
               "that passes every bound",
       .choices = {{"endpoint", "endpoint"}, {"optimal", "optimal"}},
       .field = &S::placement},
      {.name = "tolerance", .flag = "--tolerance", .metavar = "D", .section = "fidelity",
       .range = Range::AtLeast(0), .unit = "model units", .zero_means = "off",
       .help = "guaranteed (Hausdorff) deviation from the input", .field = &S::tolerance},
      {.name = "tolerance_relative", .flag = "--tolerance-relative", .metavar = "F",
       .section = "fidelity", .type = T::kFraction, .range = Range::Closed(0, 1),
       .unit = "of the bounding-box diagonal", .zero_means = "off",
       .help = "the same as a fraction of the bounding-box diagonal; with --tolerance the "
               "smaller one applies",
       .field = &S::tolerance_relative},
      {.name = "deviation_check", .flag = "--deviation-check", .section = "fidelity",
       .type = T::kEnum,
       .help = "how the tolerance is kept: mapped, a bound carried face by face along the run "
               "(fast; sums up, so it stops early); measured, every collapse judged against the "
               "input itself, both ways (keeps fewer vertices; native back end only)",
       .choices = {{"mapped", "mapped"}, {"measured", "measured"}},
       .field = &S::deviation_check},
      {.name = "feature_angle_deg", .flag = "--feature-angle", .metavar = "D",
       .section = "fidelity", .range = Range::OpenClosed(0, 180), .unit = "degrees",
       .help = "dihedral angle above which an edge is a feature edge (180: boundaries and group "
               "borders only)",
       .field = &S::feature_angle_deg},
      {.name = "max_volume_change", .flag = "--max-volume-change", .metavar = "F",
       .section = "fidelity", .type = T::kFraction, .range = Range::Closed(0, 1),
       .zero_means = "off",
       .help = "relative change of the enclosed volume (closed meshes, and each part of an "
               "assembly; an open one has none)",
       .field = &S::max_volume_change},
      {.name = "max_centroid_shift", .flag = "--max-centroid-shift", .metavar = "F",
       .section = "fidelity", .type = T::kFraction, .range = Range::Closed(0, 1),
       .unit = "of the bounding-box diagonal", .zero_means = "off", .help = "centroid shift",
       .field = &S::max_centroid_shift},
      {.name = "max_inertia_change", .flag = "--max-inertia-change", .metavar = "F",
       .section = "fidelity", .type = T::kFraction, .range = Range::Closed(0, 1),
       .zero_means = "off",
       .help = "relative change of each principal moment of inertia (of the solid; of the "
               "surface for an open mesh)",
       .field = &S::max_inertia_change},
      {.name = "max_wall_share", .flag = "--max-wall-share", .metavar = "F",
       .section = "fidelity", .type = T::kFraction, .range = Range::Closed(0, 1),
       .unit = "of the local wall thickness", .zero_means = "off",
       .help = "closed parts: the tolerance, face by face, at most this share of the wall's "
               "thickness under the face, so that thin walls keep their stiffness (0.2 held "
               "the first six frequencies within 1 % on the thin-walled parts measured)",
       .field = &S::max_wall_share},
      {.name = "max_field_change", .flag = "--max-field-change", .metavar = "F",
       .section = "fidelity", .type = T::kFraction, .range = Range::OpenClosed(0, 1),
       .help = "relative change of each face field's resultant per face group",
       .field = &S::max_field_change},
      {.name = "repair", .flag = "--repair", .section = "repair", .type = T::kEnum,
       .help = "on: weld coincident vertices, remove degenerate and duplicate facets, orient, "
               "split non-manifold vertices, and report every change; off (strict): refuse a "
               "mesh with any such defect, naming each",
       .choices = {{"off", "off"}, {"on", "on"}}, .field = &R::mode},
      {.name = "weld_tolerance", .flag = "--weld-tolerance", .metavar = "F", .section = "repair",
       .type = T::kFraction, .range = Range::Closed(0, 0.01),
       .unit = "of the bounding-box diagonal",
       .help = "repair: vertices closer than this are welded into one (0: exact duplicates only)",
       .field = &R::weld_tolerance},
      {.name = "imprint", .flag = "--imprint", .section = "repair", .type = T::kBool,
       .help = "repair: bodies exported apart that touch in a plane get their contact re-tiled "
               "as one surface shared by both (a seam between the parts, as gmsh's fragment "
               "writes it), so that tetgen and FE meshers take the assembly; off: such contacts "
               "stay as exported, faces overlapping",
       .field = &R::imprint},
      {.name = "unite_overlaps", .flag = "--unite-overlaps", .section = "repair",
       .type = T::kBool,
       .help = "repair: closed bodies that cross each other (a part exported as solids never "
               "fused) are replaced by their union, cut where their surfaces cross, so that "
               "tetgen and FE meshers take it and the overlap's volume counts once; off: they "
               "stay crossing",
       .field = &R::unite_overlaps},
      {.name = "loose_piece_share", .flag = "--loose-piece-share", .metavar = "F",
       .section = "repair", .type = T::kFraction, .range = Range::Closed(0, 1),
       .unit = "of the bodies' area", .zero_means = "keep them",
       .help = "repair: open sheets beside bodies, joined to nothing or dangling from an edge "
               "(a stray facet, a leftover face a CAD export wrote with the solid), smaller "
               "than this are removed and reported, so that the part stays a solid with its "
               "volume; a sheet part, with no body, keeps every sheet",
       .field = &R::loose_piece_share},
      {.name = "duplicate_body_offset", .flag = "--duplicate-body-offset", .metavar = "F",
       .section = "repair", .type = T::kFraction, .range = Range::Closed(0, 0.5),
       .unit = "of the bodies' mean thickness 2V/A", .zero_means = "keep them",
       .help = "repair: a closed body written twice (a part inserted twice at one place, or "
               "exported again tessellated anew) whose copy lies within this share of its "
               "thickness of it is removed and reported, so that the volume counts once and "
               "FE meshers take the part; bodies stacked on each other are not copies",
       .field = &R::duplicate_body_offset},
      {.name = "fill_holes", .flag = "--fill-holes", .section = "repair", .type = T::kEnum,
       .help = "repair: which openings are closed; small: loops of a few facets an exporter lost "
               "(at most 6 edges, a tenth of the surface); planar: also openings in one plane "
               "where the part is a solid missing a flat face (its holes kept), filled in that "
               "plane; none: every opening stays; each is reported",
       .choices = {{"small", "small"}, {"planar", "planar"}, {"none", "none"}},
       .field = &R::fill_holes},
      {.name = "backend", .flag = "--backend", .section = "backend", .type = T::kEnum,
       .help = "shared-memory threads or the emulated Cell BE",
       .choices = {{"native", "native"}, {"cell", "cell"}}, .field = &S::backend},
      {.name = "spes", .group = "cell", .flag = "--spes", .metavar = "N", .section = "backend",
       .type = T::kInt, .range = Range::Closed(1, 256), .help = "cell: SPE contexts",
       .field = &C::spes},
      {.name = "ls_cache_kib", .group = "cell", .flag = "--ls-cache-kib", .metavar = "K",
       .section = "backend", .type = T::kInt, .range = Range::Closed(1, 32768), .unit = "KiB",
       .help = "cell: software cache per local store, a power of two below local_store_kib",
       .field = &C::ls_cache_kib},
      {.name = "ls_cache_line_bytes", .group = "cell", .flag = "--ls-cache-line", .metavar = "B",
       .section = "backend", .type = T::kInt, .range = Range::Closed(16, 16384), .unit = "bytes",
       .help = "cell: software cache line, fetched by one DMA get per miss; a power of two, "
               "4 lines to a set",
       .field = &C::ls_cache_line_bytes},
      {.name = "spe_threads", .group = "cell", .flag = "--spe-threads", .metavar = "K",
       .section = "backend", .type = T::kInt, .range = Range::Closed(1, 16),
       .help = "cell: software threads per SPE (1: off)", .field = &C::spe_threads},
      {.name = "local_store_kib", .group = "cell", .section = "backend", .type = T::kInt,
       .range = Range::Closed(16, 65536), .unit = "KiB",
       .help = "cell: local store size of each SPE", .field = &C::local_store_kib},
      {.name = "reread_on_stale", .group = "cell", .section = "backend", .type = T::kBool,
       .help = "cell: on a stale cache line, re-read it (else skip the candidate)",
       .field = &C::reread_on_stale},
  };
  // clang-format on
  const SimplifyOptions defaults;
  for (OptionSpec& spec : table) spec.default_value = GetOption(spec, defaults);
  return table;
}

// The member a field names, in SimplifyOptions or its CellOptions.
template <typename V, typename O>
auto& Ref(V SimplifyOptions::*member, O& o) {
  return o.*member;
}
template <typename V, typename O>
auto& Ref(V CellOptions::*member, O& o) {
  return o.cell.*member;
}
template <typename V, typename O>
auto& Ref(V RepairOptions::*member, O& o) {
  return o.repair.*member;
}

template <typename V>
double ToDouble(V v) {
  if constexpr (std::is_enum_v<V>) {
    return static_cast<double>(static_cast<int>(v));
  } else {
    return static_cast<double>(v);
  }
}

template <typename V>
V FromDouble(double d) {
  if constexpr (std::is_enum_v<V>) {
    return static_cast<V>(static_cast<int>(d));
  } else if constexpr (std::is_same_v<V, bool>) {
    return d != 0;
  } else if constexpr (std::is_integral_v<V>) {
    // Saturated: a value beyond the type (2^64 - 1 arrives as 2^64) must stay out of range for
    // the range check, not wrap to 0 ("none") or a negative number.
    if (!(d > static_cast<double>(std::numeric_limits<V>::lowest())))
      return std::numeric_limits<V>::lowest();
    if (d >= static_cast<double>(std::numeric_limits<V>::max()))
      return std::numeric_limits<V>::max();
    return static_cast<V>(d);
  } else {
    return static_cast<V>(d);
  }
}

// The markdown cell of a text: '|' escaped.
std::string Cell(absl::string_view s) { return absl::StrReplaceAll(s, {{"|", "\\|"}}); }

}  // namespace

std::string OptionSpec::path() const {
  return cell_only() ? absl::StrCat(group, ".", name) : std::string(name);
}

const std::vector<OptionSpec>& OptionTable() {
  static const std::vector<OptionSpec>* table = new std::vector<OptionSpec>(MakeTable());
  return *table;
}

const OptionSpec* FindOption(absl::string_view path_or_flag) {
  for (const OptionSpec& s : OptionTable())
    if (s.path() == path_or_flag || (s.flag != nullptr && path_or_flag == s.flag)) return &s;
  return nullptr;
}

double GetOption(const OptionSpec& spec, const SimplifyOptions& o) {
  return std::visit([&o](auto member) { return ToDouble(Ref(member, o)); }, spec.field);
}

void SetOption(const OptionSpec& spec, double value, SimplifyOptions* o) {
  std::visit(
      [o, value](auto member) {
        auto& dst = Ref(member, *o);
        dst = FromDouble<std::remove_reference_t<decltype(dst)>>(value);
      },
      spec.field);
}

std::string FormatOptionValue(const OptionSpec& spec, double value) {
  switch (spec.type) {
    case OptionType::kBool:
      return value != 0 ? "true" : "false";
    case OptionType::kEnum: {
      const size_t i = static_cast<size_t>(value);
      return i < spec.choices.size() ? spec.choices[i].name : absl::StrCat(value);
    }
    default:
      return FormatNumber(value);
  }
}

std::string DefaultText(const OptionSpec& spec) {
  if (spec.default_note[0] != '\0') return spec.default_note;
  if (spec.type == OptionType::kEnum)
    return spec.choices[static_cast<size_t>(spec.default_value)].cli_name;
  if (spec.type == OptionType::kBool) return spec.default_value != 0 ? "on" : "off";
  return FormatOptionValue(spec, spec.default_value);
}

std::string RangeText(const OptionSpec& spec) {
  return spec.numeric() ? flags::RangeWords(spec.range, spec.unit, spec.zero_means) : "";
}

absl::Status CheckOptionValue(const OptionSpec& spec, double value, absl::string_view name) {
  if (spec.type == OptionType::kEnum) {
    if (value >= 0 && value < static_cast<double>(spec.choices.size())) return absl::OkStatus();
    return absl::InvalidArgumentError(absl::StrCat(name, " = ", value, " is not a known value"));
  }
  if (!spec.numeric() || spec.range.Contains(value) || (value == 0 && spec.zero_means[0] != '\0'))
    return absl::OkStatus();
  return flags::OutOfRange(name, FormatNumber(value), spec.range, spec.unit, spec.zero_means);
}

std::string OptionsMarkdown() {
  std::string s =
      "| option (proto, JSON) | flag | range | default | meaning |\n|---|---|---|---|---|\n";
  for (const OptionSpec& o : OptionTable()) {
    std::string flag = "—";
    if (o.flag != nullptr) {
      std::string metavar = o.metavar;
      if (o.type == OptionType::kEnum) {
        for (const OptionChoice& c : o.choices)
          absl::StrAppend(&metavar, metavar.empty() ? "" : "|", c.cli_name);
      }
      flag = absl::StrCat("`", o.flag, metavar.empty() ? "" : " ", metavar, "`");
    }
    std::string range = RangeText(o);
    if (o.type == OptionType::kEnum) {
      for (const OptionChoice& c : o.choices)
        absl::StrAppend(&range, range.empty() ? "" : ", ", "`", c.name, "`");
    }
    absl::StrAppend(&s, "| `", o.path(), "` | ", Cell(flag), " | ", Cell(range), " | ",
                    Cell(DefaultText(o)), " | ", Cell(o.help), " |\n");
  }
  return s;
}

}  // namespace femsimp
