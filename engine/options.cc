#include <cmath>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "engine/simplify.h"

namespace femsimp {
namespace {

absl::Status OutOfRange(const char* name, double value, const char* range) {
  return absl::InvalidArgumentError(
      absl::StrCat(name, " = ", value, " is out of range: must be ", range));
}

}  // namespace

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

absl::Status ValidateOptions(const SimplifyOptions& o) {
  if (!(o.ratio >= 0.0 && o.ratio < 1.0)) return OutOfRange("ratio", o.ratio, "in [0, 1)");
  if (o.ratio > 0.0 && o.target_vertices > 0)
    return absl::InvalidArgumentError("give either ratio or target_vertices, not both");
  if (o.threads < 1 || o.threads > 1024) return OutOfRange("threads", o.threads, "in [1, 1024]");
  if (!(o.max_normal_deviation_deg > 0.0 && o.max_normal_deviation_deg <= 180.0))
    return OutOfRange("max_normal_deviation", o.max_normal_deviation_deg, "in (0, 180] degrees");
  if (!(o.min_angle_deg >= 0.0 && o.min_angle_deg < 60.0))
    return OutOfRange("min_angle", o.min_angle_deg, "in [0, 60) degrees");
  if (!(o.candidate_fraction > 0.0 && o.candidate_fraction <= 1.0))
    return OutOfRange("candidate_fraction", o.candidate_fraction, "in (0, 1]");
  if (o.max_passes < 1 || o.max_passes > 100000)
    return OutOfRange("max_passes", o.max_passes, "in [1, 100000]");
  if (o.reconsider_every < 1) return OutOfRange("reconsider_every", o.reconsider_every, ">= 1");
  if (!(o.tolerance >= 0.0 && std::isfinite(o.tolerance)))
    return OutOfRange("tolerance", o.tolerance, ">= 0 and finite (0: off)");
  if (!(o.tolerance_relative >= 0.0 && o.tolerance_relative <= 1.0))
    return OutOfRange("tolerance_relative", o.tolerance_relative,
                      "in [0, 1] of the bounding-box diagonal (0: off)");
  if (!(o.feature_angle_deg > 0.0 && o.feature_angle_deg <= 180.0))
    return OutOfRange("feature_angle", o.feature_angle_deg, "in (0, 180] degrees");
  if (!(o.max_volume_change >= 0.0 && o.max_volume_change <= 1.0))
    return OutOfRange("max_volume_change", o.max_volume_change, "in [0, 1] (0: off)");
  if (!(o.max_centroid_shift >= 0.0 && o.max_centroid_shift <= 1.0))
    return OutOfRange("max_centroid_shift", o.max_centroid_shift, "in [0, 1] (0: off)");
  if (!(o.max_field_change > 0.0 && o.max_field_change <= 1.0))
    return OutOfRange("max_field_change", o.max_field_change, "in (0, 1]");
  if (o.cost != CostKind::kGaussianCurvature && o.cost != CostKind::kQuadric)
    return absl::InvalidArgumentError("cost: unknown kind");
  if (o.backend == Backend::kCell) {
    const CellOptions& c = o.cell;
    if (c.spes < 1 || c.spes > 256) return OutOfRange("spes", c.spes, "in [1, 256]");
    if (c.local_store_kib < 16 || c.local_store_kib > 65536)
      return OutOfRange("local_store_kib", c.local_store_kib, "in [16, 65536]");
    if (c.ls_cache_kib < 1 || c.ls_cache_kib >= c.local_store_kib)
      return OutOfRange("ls_cache_kib", c.ls_cache_kib, "in [1, local_store_kib)");
    if ((c.ls_cache_kib & (c.ls_cache_kib - 1)) != 0)
      return OutOfRange("ls_cache_kib", c.ls_cache_kib, "a power of two (cache sets are)");
    if (c.spe_threads < 1 || c.spe_threads > 16)
      return OutOfRange("spe_threads", c.spe_threads, "in [1, 16]");
  }
  return absl::OkStatus();
}

}  // namespace femsimp
