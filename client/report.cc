#include "client/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/fe_report.h"
#include "common/json.h"
#include "engine/option_table.h"

namespace femsimp::cli {
namespace {

uint64_t TotalRejections(const PassStats& p) {
  uint64_t n = 0;
  for (uint64_t r : p.rejections) n += r;
  return n;
}

std::string JsonStrings(const std::vector<std::string>& list) {
  std::string s = "[";
  for (size_t i = 0; i < list.size(); ++i) absl::StrAppend(&s, i ? ", " : "", JsonString(list[i]));
  return s + "]";
}

std::string CellJson(const CellPassCounters& c) {
  return absl::StrCat(
      "{\"cache_hits\": ", c.cache_hits, ", \"cache_misses\": ", c.cache_misses,
      ", \"hit_ratio\": ", JsonNumber(c.hit_ratio()), ", \"stale_detected\": ", c.stale_detected,
      ", \"stale_reread\": ", c.stale_reread, ", \"stale_skipped\": ", c.stale_skipped,
      ", \"dma_transfers\": ", c.dma_transfers, ", \"dma_bytes\": ", c.dma_bytes,
      ", \"atomic_ops\": ", c.atomic_ops, ", \"thread_switches\": ", c.thread_switches,
      ", \"busy_cycles\": ", c.busy_cycles, ", \"modeled_cycles\": ", c.modeled_cycles, "}");
}

// The options in the table's order and names; the cell group as an object, cell back end only.
std::string OptionsJson(const SimplifyOptions& o) {
  std::vector<std::string> top, cell;
  for (const OptionSpec& spec : OptionTable()) {
    if (spec.cell_only() && o.backend != Backend::kCell) continue;
    const double v = GetOption(spec, o);
    std::string value;
    switch (spec.type) {
      case OptionType::kReal:
      case OptionType::kFraction:
        value = JsonNumber(v);
        break;
      case OptionType::kEnum:
        value = JsonString(FormatOptionValue(spec, v));
        break;
      default:  // integers and booleans print as JSON has them
        value = FormatOptionValue(spec, v);
    }
    (spec.cell_only() ? cell : top).push_back(absl::StrCat(JsonString(spec.name), ": ", value));
  }
  if (!cell.empty()) top.push_back(absl::StrCat("\"cell\": {", absl::StrJoin(cell, ", "), "}"));
  return absl::StrCat("{", absl::StrJoin(top, ", "), "}");
}

std::string PassJson(const PassStats& p) {
  std::string rej = "{";
  for (int i = 0; i < static_cast<int>(Reject::kCount); ++i)
    absl::StrAppend(&rej, i ? ", " : "", JsonString(RejectName(static_cast<Reject>(i))), ": ",
                    p.rejections[i]);
  rej += "}";
  std::string s = absl::StrCat(
      "{\"pass\": ", p.pass, ", \"candidates\": ", p.candidates, ", \"tried\": ", p.tried,
      ", \"removed\": ", p.removed, ", \"lock_conflicts\": ", p.lock_conflicts,
      ", \"inconsistent\": ", p.inconsistent, ", \"rounds\": ", p.rounds,
      ", \"seam_points_removed\": ", p.seam_points_removed, ", \"placed\": ", p.placed,
      ", \"placed_on_lines\": ", p.placed_on_lines, ", \"boxes_kept\": ", p.boxes_kept,
      ", \"rejections\": ", rej, ", \"vertices_left\": ", p.vertices_left,
      ", \"seconds\": ", JsonNumber(p.seconds), ", \"busy_seconds\": ", JsonNumber(p.busy_seconds));
  if (p.cell) {
    absl::StrAppend(&s, ", \"cell\": ", CellJson(*p.cell), ", \"cell_per_spe\": [");
    for (size_t i = 0; i < p.cell_per_spe.size(); ++i)
      absl::StrAppend(&s, i ? ", " : "", CellJson(p.cell_per_spe[i]));
    absl::StrAppend(&s, "], \"ppe_cycles\": ", p.ppe_cycles,
                    ", \"spe_start_cycles\": ", p.spe_start_cycles,
                    ", \"modeled_pass_cycles\": ", p.modeled_pass_cycles);
  }
  return s + "}";
}

std::string Vec3Json(const DVec3& v) {
  return absl::StrCat("[", JsonNumber(v.x), ", ", JsonNumber(v.y), ", ", JsonNumber(v.z), "]");
}

std::string MassJson(const MassSummary& m) {
  return absl::StrCat("{\"solid\": ", m.solid ? "true" : "false", ", \"",
                      m.solid ? "volume" : "area", "\": ", JsonNumber(m.measure),
                      m.solid ? absl::StrCat(", \"area\": ", JsonNumber(m.area),
                                             ", \"mean_thickness\": ", JsonNumber(MeanThickness(m)))
                              : std::string(),
                      ", \"centroid\": ", Vec3Json(m.centroid), ", \"principal_moments\": [",
                      JsonNumber(m.principal_moments[0]), ", ", JsonNumber(m.principal_moments[1]),
                      ", ", JsonNumber(m.principal_moments[2]), "], \"principal_axes\": [",
                      Vec3Json(m.principal_axes[0]), ", ", Vec3Json(m.principal_axes[1]), ", ",
                      Vec3Json(m.principal_axes[2]), "]}");
}

std::string CrossingsJson(const SoupCrossings& c) {
  const SoupCrossings::Overlaps& o = c.overlaps;
  const std::string overlaps =
      o.pairs == 0 ? "{\"pairs\": 0}"
                   : absl::StrCat("{\"pairs\": ", o.pairs, ", \"area\": ", JsonNumber(o.area),
                                  ", \"faces\": [", o.face_a, ", ", o.face_b, "], \"at\": [",
                                  JsonNumber(o.at[0]), ", ", JsonNumber(o.at[1]), ", ",
                                  JsonNumber(o.at[2]), "]}");
  const SoupCrossings::Folds& f = c.folds;
  const std::string folds =
      f.pairs == 0 ? "{\"pairs\": 0}"
                   : absl::StrCat("{\"pairs\": ", f.pairs, ", \"faces\": [", f.face_a, ", ",
                                  f.face_b, "], \"at\": [", JsonNumber(f.at[0]), ", ",
                                  JsonNumber(f.at[1]), ", ", JsonNumber(f.at[2]), "]}");
  const std::string apart = absl::StrCat(", \"overlaps\": ", overlaps, ", \"folds\": ", folds,
                                         ", \"cut_short\": ", c.cut_short ? "true" : "false", "}");
  if (c.pairs == 0) return absl::StrCat("{\"pairs\": 0", apart);
  return absl::StrCat("{\"pairs\": ", c.pairs, ", \"faces\": [", c.face_a, ", ", c.face_b,
                      "], \"at\": [", JsonNumber(c.at[0]), ", ", JsonNumber(c.at[1]), ", ",
                      JsonNumber(c.at[2]), "]", apart);
}

std::string PartsJson(const std::vector<SimplifyResult::PartVolume>& parts) {
  std::string s = "[";
  for (size_t i = 0; i < parts.size(); ++i)
    absl::StrAppend(&s, i ? ", " : "", "{\"input_volume\": ", JsonNumber(parts[i].input),
                    ", \"output_volume\": ", JsonNumber(parts[i].output), "}");
  return s + "]";
}

std::string FidelityJson(const FidelityFigures& f) {
  return absl::StrCat("{\"feature_edges\": ", f.feature_edges,
                      ", \"corner_vertices\": ", f.corner_vertices,
                      ", \"tolerance_abs\": ", JsonNumber(f.tolerance_abs),
                      ", \"deviation_bound\": ", JsonNumber(f.deviation_bound),
                      ", \"volume_change\": ", JsonNumber(f.volume_change),
                      ", \"centroid_shift\": ", JsonNumber(f.centroid_shift),
                      ", \"max_field_change\": ", JsonNumber(f.max_field_change),
                      ", \"inertia_change\": ", JsonNumber(f.inertia_change),
                      ", \"wall_limited_share\": ", JsonNumber(f.wall_limited_share),
                      ", \"thinnest_wall\": ", JsonNumber(f.thinnest_wall),
                      ", \"output_crossings\": ", CrossingsJson(f.output_crossings),
                      ", \"coordinates\": {\"magnitude\": ", JsonNumber(f.coordinates.magnitude),
                      ", \"spacing\": ", JsonNumber(f.coordinates.spacing),
                      ", \"diagonal\": ", JsonNumber(f.coordinates.diagonal), "}",
                      ",\n    \"input_mass\": ", MassJson(f.input_mass),
                      ",\n    \"output_mass\": ", MassJson(f.output_mass),
                      ",\n    \"parts\": ", PartsJson(f.parts), "}");
}

std::string FaceDataJson(const RunReport& r) {
  std::string s =
      absl::StrCat("{\"groups\": ", r.face_groups, ", \"fields\": ", JsonStrings(r.face_fields));
  absl::StrAppend(&s, ", \"dropped\": ",
                  r.dropped_face_data.empty() ? "null" : JsonString(r.dropped_face_data), "}");
  return s;
}

std::string RepairJson(const RunReport& r) {
  const RepairReport& rep = r.repair;
  std::string counts;
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    absl::StrAppend(&counts, k ? ", " : "", JsonString(RepairKindName(static_cast<RepairKind>(k))),
                    ": ", rep.counts[k]);
  std::string s = absl::StrCat(
      "{\"mode\": ", JsonString(r.options.repair.mode == RepairMode::kOn ? "on" : "off"),
      ", \"changes\": ", rep.num_changes(), ", \"counts\": {", counts,
      "}, \"weld_tolerance\": ", JsonNumber(rep.weld_tolerance_relative),
      ", \"weld_tolerance_abs\": ", JsonNumber(rep.weld_tolerance_absolute),
      ", \"diagonal\": ", JsonNumber(rep.diagonal), ", \"records\": [");
  for (size_t i = 0; i < rep.records.size(); ++i) {
    const RepairRecord& rec = rep.records[i];
    absl::StrAppend(&s, i ? "," : "", "\n    {\"kind\": ", JsonString(RepairKindName(rec.kind)),
                    ", \"facet\": ", rec.facet, ", \"vertex\": ", rec.vertex, ", \"at\": [",
                    JsonNumber(rec.at[0]), ", ", JsonNumber(rec.at[1]), ", ", JsonNumber(rec.at[2]),
                    "], \"detail\": ", JsonString(rec.detail), "}");
  }
  absl::StrAppend(&s, rep.records.empty() ? "]}" : "\n  ]}");
  return s;
}

// Measure and principal moments in and out (unit density), and the worst moment's change.
std::string MassSummaryLine(const FidelityFigures& f) {
  const MassSummary &in = f.input_mass, &out = f.output_mass;
  const auto moments = [](const MassSummary& m) {
    return absl::StrFormat("%.4g %.4g %.4g", m.principal_moments[0], m.principal_moments[1],
                           m.principal_moments[2]);
  };
  return absl::StrFormat(
      "mass:     %s %.6g -> %.6g, principal moments of inertia (unit density) %s -> %s (worst "
      "change %.4f%%)\n",
      in.solid ? "volume" : "area (open surface)", in.measure, out.measure, moments(in),
      moments(out), 100 * f.inertia_change);
}

// A body inside another that shares its whole surface with it is in none of the mass figures
// (engine/repair.h, kSharedShellLeft): said beside them, whether or not its record is listed.
std::string SharedShellWarning(const RepairReport& repair) {
  const size_t left = repair.count(RepairKind::kSharedShellLeft);
  if (left == 0) return "";
  return absl::StrFormat(
      "warning:  the volume, the moments and the mass budgets leave out %u bod%s inside another "
      "that share%s %s whole surface with it, kept once as a cavity's wall (shared_shell_left in "
      "the repair report)\n",
      left, left == 1 ? "y" : "ies", left == 1 ? "s" : "", left == 1 ? "its" : "their");
}

// The parts of an assembly (meeting at seams, or one inside another), each a solid of its own
// volume: the first few, and the one that
// changed most.
std::string PartsLine(const std::vector<SimplifyResult::PartVolume>& parts) {
  if (parts.empty()) return "";
  constexpr size_t kListed = 4;
  const auto change = [](const SimplifyResult::PartVolume& p) {
    return p.input != 0.0 ? (p.output - p.input) / p.input : 0.0;
  };
  const auto part = [&](size_t i) {
    return absl::StrFormat("part %u %.6g -> %.6g (%+.4f%%)", i + 1, parts[i].input, parts[i].output,
                           100 * change(parts[i]));
  };
  std::string s =
      absl::StrFormat("parts:    %u solids of an assembly, volume each: ", parts.size());
  size_t worst = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    if (std::fabs(change(parts[i])) > std::fabs(change(parts[worst]))) worst = i;
    if (i < kListed) absl::StrAppend(&s, i ? ", " : "", part(i));
  }
  if (parts.size() > kListed)
    absl::StrAppend(&s, ", ", parts.size() - kListed, " more; the most changed: ", part(worst));
  return s + "\n";
}

// An output that intersects itself is refused by the mesher that comes next; the collapses make no
// crossing unless allowed to (docs/FIDELITY.md § 9), so they came with the input, which repair
// cannot untangle (a thin wall exported with facets as large as the part).
std::string CrossingsWarning(const SoupCrossings& c, bool allowed) {
  std::string overlaps;
  if (c.overlaps.pairs > 0)
    overlaps = absl::StrCat(
        "warning:  OUT has overlapping faces: ", DescribeOverlaps(c),
        allowed ? "; from the input or the run (--allow-self-intersections)"
                : "; kept from the input (the simplification makes none)",
        "; tetgen and most FE meshers refuse overlapping faces (--imprint makes each planar "
        "contact one surface shared by the bodies, as gmsh's fragment exports it)\n");
  if (c.folds.pairs > 0)
    absl::StrAppend(&overlaps, "warning:  OUT has folded faces: ", DescribeFolds(c),
                    allowed ? "; from the input or the run (--allow-self-intersections)"
                            : "; kept from the input, where no flip of their edge unfolds them "
                              "(the repair report's fold_left says why)",
                    "; tetgen and most FE meshers refuse faces lying on each other\n");
  if (c.pairs == 0) return overlaps;
  return absl::StrCat(
      overlaps, "warning:  OUT intersects itself: ", DescribeCrossings(c), "; ",
      allowed ? "--allow-self-intersections let the run make crossings"
              : "the input's own crossings, kept (the simplification makes none)",
      "; a mesher such as tetgen refuses it (a finer export avoids crossings within a part; "
      "--unite-overlaps replaces closed bodies exported overlapping by their union)\n");
}

// A solid's mean thickness against the tolerance. Each side of a wall may move by the
// tolerance, so where the tolerance reaches half the thickness a wall may lose or double all of
// it; the mass budgets hold totals, not a wall's local thickness, and its stiffness follows that
// (docs/FIDELITY.md § 5). The wall rule (max_wall_share) holds it, face by face: then the line
// says where it lowered the tolerance instead of warning.
std::string WallLines(const FidelityFigures& f, double max_wall_share) {
  const double thickness = MeanThickness(f.input_mass);
  if (thickness <= 0.0 || f.tolerance_abs <= 0.0) return "";
  const double share = f.tolerance_abs / thickness;
  std::string s = absl::StrFormat(
      "walls:    mean thickness 2V/A %.4g; the tolerance is %.0f%% of it", thickness, 100 * share);
  if (f.thinnest_wall > 0.0)
    return absl::StrCat(
        s, absl::StrFormat("; the wall rule lowered it on %.1f%% of the surface (thinnest wall "
                           "%.4g)\n",
                           100 * f.wall_limited_share, f.thinnest_wall));
  if (max_wall_share > 0.0 && !f.parts.empty())  // open sheets: no inside to cast rays into
    return absl::StrCat(s,
                        "; --max-wall-share holds closed parts only: not applied to an "
                        "assembly whose parts meet at seams\n");
  if (max_wall_share > 0.0)  // the rays looked no farther than where a wall lowers nothing
    return absl::StrCat(s, absl::StrFormat("; no wall thinner than %.4g (the tolerance over "
                                           "--max-wall-share): the wall rule lowered it nowhere\n",
                                           f.tolerance_abs / max_wall_share));
  absl::StrAppend(&s, "\n");
  if (share >= kThinWallShare)
    absl::StrAppend(&s, absl::StrFormat("warning:  the tolerance is %.0f%% of the mean wall "
                                        "thickness: a wall may thin or thicken by up to twice "
                                        "the tolerance, which the mass budgets do not hold, and "
                                        "its stiffness with it (femsimp check measures it; "
                                        "--max-wall-share 0.2 or a smaller --tolerance-relative "
                                        "keeps it)\n",
                                        100 * share));
  return s;
}

}  // namespace

std::string RepairSummary(const RepairReport& r, size_t max_records) {
  const size_t changes = r.num_changes();
  // Folds, holes and crossings left are what the mesher next refuses: listed where nothing
  // changed too.
  if (changes == 0 && r.count(RepairKind::kFoldLeft) == 0 && r.count(RepairKind::kHoleLeft) == 0 &&
      r.count(RepairKind::kCrossingLeft) == 0)
    return "repair:   no changes\n";
  std::string s =
      changes == 0
          ? std::string("repair:   no changes\n")
          : absl::StrFormat("repair:   %u change%s (weld tolerance %.3g of the diagonal = %.3g)\n",
                            changes, changes == 1 ? "" : "s", r.weld_tolerance_relative,
                            r.weld_tolerance_absolute);
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (r.counts[k] > 0)
      absl::StrAppend(&s, absl::StrFormat("  %-22s %u\n",
                                          RepairKindName(static_cast<RepairKind>(k)), r.counts[k]));
  // The first record of every kind, then the rest in order, up to max_records: a kind with
  // many records (the vertices a removal left unused) does not hide the others' one.
  std::vector<bool> shown(r.records.size(), false);
  size_t listed = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    for (size_t i = 0; i < r.records.size() && listed < max_records; ++i)
      if (static_cast<size_t>(r.records[i].kind) == k) {
        shown[i] = true;
        ++listed;
        break;
      }
  for (size_t i = 0; i < r.records.size() && listed < max_records; ++i)
    if (!shown[i]) {
      shown[i] = true;
      ++listed;
    }
  for (size_t i = 0; i < r.records.size(); ++i)
    if (shown[i]) absl::StrAppend(&s, "  ", r.records[i].ToString(), "\n");
  size_t recorded = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k) recorded += r.counts[k];
  if (recorded > listed)
    absl::StrAppend(
        &s, "  ... ", recorded - listed,
        " more (--repair-details lists them, --stats-json has them under \"repair\")\n");
  return s;
}

FidelityFigures FidelityFigures::Of(const SimplifyResult& r) {
  FidelityFigures f;
  f.feature_edges = r.feature_edges;
  f.corner_vertices = r.corner_vertices;
  f.tolerance_abs = r.tolerance_abs;
  f.deviation_bound = r.deviation_bound;
  f.volume_change = r.volume_change;
  f.centroid_shift = r.centroid_shift;
  f.max_field_change = r.max_field_change;
  f.input_mass = r.input_mass;
  f.output_mass = r.output_mass;
  f.inertia_change = r.inertia_change;
  f.wall_limited_share = r.wall_limited_share;
  f.thinnest_wall = r.thinnest_wall;
  f.output_crossings = r.output_crossings;
  f.coordinates = r.coordinates;
  f.parts = r.parts;
  return f;
}

std::string PassTableHeader(Backend backend) {
  std::string h = absl::StrFormat("%5s %12s %10s %10s %10s %10s %9s", "pass", "vertices", "removed",
                                  "tried", "lock_confl", "rejected", "seconds");
  if (backend == Backend::kCell) absl::StrAppend(&h, absl::StrFormat(" %9s", "cache_hit"));
  return h;
}

std::string ProgressLine(const PassStats& p, uint64_t input_vertices, const SimplifyOptions& o) {
  uint64_t target = o.target_vertices
                        ? o.target_vertices
                        : static_cast<uint64_t>(o.ratio * static_cast<double>(input_vertices));
  std::string bar;
  if (target > 0 && target < input_vertices) {
    const double fraction =
        std::clamp(static_cast<double>(input_vertices - std::min(input_vertices, p.vertices_left)) /
                       static_cast<double>(input_vertices - target),
                   0.0, 1.0);
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth + 0.5);
    bar = absl::StrFormat("[%s%s] %3.0f%% ", std::string(filled, '#'),
                          std::string(kWidth - filled, '.'), 100 * fraction);
  }
  uint64_t rejected = 0;
  for (uint64_t r : p.rejections) rejected += r;
  std::string s = absl::StrFormat(
      "\r%spass %d: %u vertices, -%u, tried %u, locks %u, rejected %u, %.3f s", bar, p.pass,
      p.vertices_left, p.removed, p.tried, p.lock_conflicts, rejected, p.seconds);
  if (p.cell) absl::StrAppend(&s, absl::StrFormat(", cache %.1f%%", 100 * p.cell->hit_ratio()));
  return s + "\x1b[K";  // clear what a longer previous line left
}

std::string PassTableRow(const PassStats& p, Backend backend) {
  std::string r =
      absl::StrFormat("%5d %12u %10u %10u %10u %10u %9.3f", p.pass, p.vertices_left, p.removed,
                      p.tried, p.lock_conflicts, TotalRejections(p), p.seconds);
  if (backend == Backend::kCell) {
    if (p.cell) {
      absl::StrAppend(&r, absl::StrFormat(" %8.1f%%", 100.0 * p.cell->hit_ratio()));
    } else {
      absl::StrAppend(&r, absl::StrFormat(" %9s", "-"));
    }
  }
  return r;
}

std::string Summary(const RunReport& r) {
  auto pct = [](uint64_t out, uint64_t in) {
    return in ? 100.0 * static_cast<double>(out) / static_cast<double>(in) : 0.0;
  };
  // Why it stopped, in words, and which rule refused the most. At the pass limit collapses may
  // still be left: the run was cut, not finished.
  const std::string refused =
      r.limiting_rule.empty() ? "" : absl::StrCat("; refused most by ", r.limiting_rule);
  const std::string why =
      r.stop_reason == "max_passes"
          ? absl::StrCat(r.stop_reason,
                         " (the pass limit: more passes, --max-passes, may remove more", refused,
                         ")")
      : r.limiting_rule.empty()
          ? r.stop_reason
          : absl::StrCat(r.stop_reason, " (no valid collapse left", refused, ")");
  std::string s = absl::StrFormat(
      "vertices: %u -> %u (%.1f%%)\nfaces:    %u -> %u (%.1f%%)\npasses:   %u, stop reason: %s\n",
      r.input_vertices, r.output_vertices, pct(r.output_vertices, r.input_vertices), r.input_faces,
      r.output_faces, pct(r.output_faces, r.input_faces), r.passes.size(), why);
  for (const std::string& w : r.input_warnings) absl::StrAppend(&s, "warning:  ", w, "\n");
  absl::StrAppend(&s, RepairSummary(r.repair, r.repair_details ? r.repair.records.size()
                                                               : kSummaryRepairRecords));
  const FidelityFigures& f = r.fidelity;
  absl::StrAppend(&s, "fidelity: ",
                  f.tolerance_abs > 0 ? absl::StrFormat("deviation bound %g (tolerance %g)",
                                                        f.deviation_bound, f.tolerance_abs)
                                      : std::string("no tolerance"),
                  absl::StrFormat(", volume %+.4f%%, centroid shift %.4f%% of the diagonal\n",
                                  100 * f.volume_change, 100 * f.centroid_shift));
  absl::StrAppend(&s, MassSummaryLine(f), SharedShellWarning(r.repair), PartsLine(f.parts),
                  WallLines(f, r.options.max_wall_share),
                  CrossingsWarning(f.output_crossings, r.options.allow_self_intersections));
  absl::StrAppend(&s,
                  absl::StrFormat("features: %u edges, %u corners (feature angle %g deg)\n",
                                  f.feature_edges, f.corner_vertices, r.options.feature_angle_deg));
  uint64_t seam_points = 0;
  for (const PassStats& p : r.passes) seam_points += p.seam_points_removed;
  if (seam_points > 0)
    absl::StrAppend(&s, "seams:    ", seam_points,
                    " seam points slid along their seams (every part at once)\n");
  uint64_t placed = 0, placed_on_lines = 0;
  for (const PassStats& p : r.passes) {
    placed += p.placed;
    placed_on_lines += p.placed_on_lines;
  }
  if (r.options.placement == Placement::kOptimal) {
    absl::StrAppend(&s, "placement: ", placed,
                    r.options.deviation_check == DeviationCheck::kMeasured
                        ? " full-edge collapses (vertices merged where a mass budget or the "
                          "tolerance refused the half-edge collapse"
                        : " full-edge collapses (vertices merged where a mass budget refused the "
                          "half-edge collapse");
    // Only the measured check moves lines (CollapseRule::holds_placed_lines).
    if (r.options.deviation_check == DeviationCheck::kMeasured)
      absl::StrAppend(&s, "; ", placed_on_lines, " of them on feature lines");
    s += ")\n";
  }
  if (r.face_groups > 0 || !r.face_fields.empty()) {
    absl::StrAppend(&s, "face data: ", r.face_groups, " groups");
    if (!r.face_fields.empty())
      absl::StrAppend(&s, "; fields ", absl::StrJoin(r.face_fields, ", "),
                      absl::StrFormat(" (worst resultant change %.3f%%, limit %.3f%%)",
                                      100 * f.max_field_change, 100 * r.options.max_field_change));
    if (!r.dropped_face_data.empty())
      absl::StrAppend(&s, "; not in the output: ", r.dropped_face_data);
    else if (absl::EndsWithIgnoreCase(r.output_path, ".stl"))
      s += "; the STL output is ASCII, one solid per group";
    s += "\n";
  }
  double speedup = r.engine_seconds > 0 ? r.busy_seconds / r.engine_seconds : 0.0;
  const std::string crossings_check =
      r.server.empty() ? absl::StrFormat(", crossings check %.3f s", r.crossings_seconds) : "";
  absl::StrAppend(&s, absl::StrFormat("time:     load %.3f s, engine %.3f s (parallel speedup "
                                      "%.2f)%s, write %.3f s\n",
                                      r.load_seconds, r.engine_seconds, speedup, crossings_check,
                                      r.write_seconds));
  if (!r.server.empty())
    absl::StrAppend(&s,
                    absl::StrFormat("server:   %s, job %s, queued %.3f s, rpc %.3f s%s\n", r.server,
                                    r.job_id, r.queue_seconds, r.transfer_seconds,
                                    r.attempts > 1 ? absl::StrCat(", attempts ", r.attempts) : ""));
  absl::StrAppend(&s, "output:   ", r.output_path, "\n");
  for (const std::string& w : r.output_warnings) absl::StrAppend(&s, "warning:  ", w, "\n");
  if (r.fe_check) absl::StrAppend(&s, FeCheckTable(*r.fe_check, {r.input_path, r.output_path}));
  return s;
}

std::string ReportJson(const RunReport& r) {
  std::string s = absl::StrCat(
      "{\n  \"input\": {\"path\": ", JsonString(r.input_path), ", \"vertices\": ", r.input_vertices,
      ", \"faces\": ", r.input_faces, ", \"warnings\": ", JsonStrings(r.input_warnings),
      "},\n  \"output\": {\"path\": ", JsonString(r.output_path),
      ", \"vertices\": ", r.output_vertices, ", \"faces\": ", r.output_faces,
      ", \"warnings\": ", JsonStrings(r.output_warnings),
      "},\n  \"engine_seconds\": ", JsonNumber(r.engine_seconds),
      ",\n  \"busy_seconds\": ", JsonNumber(r.busy_seconds), ",\n  \"parallel_speedup\": ",
      JsonNumber(r.engine_seconds > 0 ? r.busy_seconds / r.engine_seconds : 0.0),
      ",\n  \"load_seconds\": ", JsonNumber(r.load_seconds),
      ",\n  \"write_seconds\": ", JsonNumber(r.write_seconds),
      ",\n  \"crossings_seconds\": ", JsonNumber(r.crossings_seconds),
      ",\n  \"stop_reason\": ", JsonString(r.stop_reason),
      ",\n  \"limiting_rule\": ", JsonString(r.limiting_rule),
      ",\n  \"modeled_cycles\": ", r.modeled_cycles, ",\n  \"options\": ", OptionsJson(r.options),
      ",\n  \"fidelity\": ", FidelityJson(r.fidelity), ",\n  \"face_data\": ", FaceDataJson(r),
      ",\n  \"repair\": ", RepairJson(r));
  if (!r.server.empty())
    absl::StrAppend(&s, ",\n  \"remote\": {\"server\": ", JsonString(r.server),
                    ", \"job_id\": ", JsonString(r.job_id),
                    ", \"queue_seconds\": ", JsonNumber(r.queue_seconds),
                    ", \"rpc_seconds\": ", JsonNumber(r.transfer_seconds),
                    ", \"attempts\": ", r.attempts, "}");
  if (r.fe_check) absl::StrAppend(&s, ",\n  \"fe_check\": ", FeCheckJson(*r.fe_check, {"", ""}, 2));
  absl::StrAppend(&s, ",\n  \"passes\": [");
  for (size_t i = 0; i < r.passes.size(); ++i)
    absl::StrAppend(&s, i ? ",\n    " : "\n    ", PassJson(r.passes[i]));
  absl::StrAppend(&s, r.passes.empty() ? "]\n}\n" : "\n  ]\n}\n");
  return s;
}

absl::Status WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return absl::PermissionDeniedError(absl::StrCat(path, ": cannot open for writing"));
  f << text;
  f.close();
  if (!f) return absl::DataLossError(absl::StrCat(path, ": write failed"));
  return absl::OkStatus();
}

}  // namespace femsimp::cli
