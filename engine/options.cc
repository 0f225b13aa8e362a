#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "cellsim/software_cache.h"
#include "engine/option_table.h"
#include "engine/simplify.h"

namespace femsimp {

const char* RejectName(Reject r) {
  switch (r) {
#define FEMSIMP_RULE(reason, name, type) \
  case Reject::reason:                   \
    return name;
#include "engine/rules/rule_list.inc"
#undef FEMSIMP_RULE
    case Reject::kCount:
      break;
  }
  return "unknown";
}

const char* CostKindName(CostKind c) {
  switch (c) {
    case CostKind::kGaussianCurvature:
      return "gaussian_curvature";
    case CostKind::kQuadric:
      return "quadric";
    case CostKind::kDeviation:
      return "deviation";
  }
  return "unknown";
}

const char* StopReasonName(StopReason r) {
  switch (r) {
    case StopReason::kTargetReached:
      return "target_reached";
    case StopReason::kNoProgress:
      return "no_progress";
    case StopReason::kMaxPasses:
      return "max_passes";
    case StopReason::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

SimplifyOptions PresetOptions(Preset preset) {
  SimplifyOptions o;
  o.preset = preset;
  if (preset == Preset::kPaper) {
    o.tolerance_relative = 0.0;
    o.max_volume_change = 0.0;
    o.strict_min_angle = true;
    o.periodic_retry = true;
    o.allow_self_intersections = true;
    o.schedule = Schedule::kFree;
    o.cost = CostKind::kGaussianCurvature;
  }
  return o;
}

absl::Status ValidateOptions(const SimplifyOptions& o) {
  // Each value in its range (the table's words); the cell options only with the cell back end,
  // which is the only one that reads them.
  for (const OptionSpec& spec : OptionTable()) {
    if (spec.cell_only() && o.backend != Backend::kCell) continue;
    if (absl::Status s = CheckOptionValue(spec, GetOption(spec, o), spec.name); !s.ok()) return s;
  }
  // The rules between options.
  if (o.ratio > 0.0 && o.target_vertices > 0)
    return absl::InvalidArgumentError("give either ratio or target_vertices, not both");
  if (o.max_wall_share > 0.0) {
    if (!(o.tolerance > 0.0) && !(o.tolerance_relative > 0.0))
      return absl::InvalidArgumentError(
          "max_wall_share limits the tolerance where walls are thin: give a tolerance "
          "(tolerance or tolerance_relative) too");
  }
  if (o.backend == Backend::kCell) {
    if (o.deviation_check == DeviationCheck::kMeasured)
      return absl::InvalidArgumentError(
          "deviation_check = measured runs on the native back end only: the cell back end has "
          "no model of the input's pieces in its memory (use deviation_check = mapped)");
    const CellOptions& c = o.cell;
    if (c.ls_cache_kib >= c.local_store_kib)
      return absl::InvalidArgumentError(absl::StrCat("ls_cache_kib = ", c.ls_cache_kib,
                                                     " is out of range: must be below ",
                                                     "local_store_kib = ", c.local_store_kib));
    if ((c.ls_cache_kib & (c.ls_cache_kib - 1)) != 0)
      return absl::InvalidArgumentError(
          absl::StrCat("ls_cache_kib = ", c.ls_cache_kib,
                       " is out of range: must be a power of two (cache sets are)"));
    if ((c.ls_cache_line_bytes & (c.ls_cache_line_bytes - 1)) != 0)
      return absl::InvalidArgumentError(
          absl::StrCat("ls_cache_line_bytes = ", c.ls_cache_line_bytes,
                       " is out of range: must be a power of two (lines are aligned to it)"));
    const size_t ways = cellsim::CacheConfig{}.ways;
    if (size_t(c.ls_cache_line_bytes) * ways > size_t(c.ls_cache_kib) * 1024)
      return absl::InvalidArgumentError(
          absl::StrCat("ls_cache_line_bytes = ", c.ls_cache_line_bytes, " is out of range: ", ways,
                       " lines (one set) must fit in ls_cache_kib = ", c.ls_cache_kib, " KiB"));
  }
  return absl::OkStatus();
}

}  // namespace femsimp
