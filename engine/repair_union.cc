#include "engine/repair_union.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/overlap_union.h"
#include "engine/repair_recheck.h"
#include "engine/repair_uncross.h"

namespace femsimp {

static_assert(kNoUnionSource == kNoStepVertex);

absl::StatusOr<RepairResult> UniteRepaired(RawMesh& mesh, const RepairOptions& options,
                                           RepairResult repaired) {
  UnionResult u = UniteOverlaps(mesh);
  // A body crossing itself (a vertex written wrongly) is none a union takes: where one is, the
  // crossings within surfaces are taken out first (as the step after the union would), then
  // the bodies united.
  if (options.take_out_crossings &&
      std::any_of(u.left.begin(), u.left.end(),
                  [](const UnionLeft& left) { return left.body_crosses_itself; })) {
    const size_t removed = repaired.report.count(RepairKind::kCrossingRemoved);
    absl::StatusOr<RepairResult> uncrossed =
        UncrossRepaired(mesh, options, std::move(repaired), CrossingScope::kWithinSurfaces);
    if (!uncrossed.ok()) return uncrossed;
    repaired = *std::move(uncrossed);
    if (repaired.report.count(RepairKind::kCrossingRemoved) > removed) u = UniteOverlaps(mesh);
  }
  // The other repairs again, on the united mesh: a new point closer to a corner than the weld
  // tolerance, a needle where the surfaces cross at a corner. Should they fail or leave a defect
  // the first run did not, the bodies stay as exported.
  RepairOptions again = options;
  again.unite_overlaps = false;
  again.take_out_crossings = false;  // the union's own scan has looked at its facets
  again.imprint = false;
  absl::StatusOr<RepairResult> checked = absl::InternalError("not run");
  if (!u.united.empty()) {
    checked = RepairMesh(u.mesh, again);
    const std::string why = RecheckObjection(
        checked,
        [&](RepairKind kind) {
          return IsRepairChange(kind) ? SIZE_MAX : repaired.report.count(kind);
        },
        "the union would leave a defect");
    if (!why.empty()) {
      for (const UnitedBodies& b : u.united)
        u.left.push_back({b.first_facet, b.at, absl::StrCat("after the union: ", why)});
      u.united.clear();
    } else {
      mesh = std::move(u.mesh);
    }
  }
  ReportMerger merge(repaired, mesh, options.max_records_per_kind);
  const std::vector<uint32_t> first_facet = repaired.facet_origin;
  for (const UnionLeft& left : u.left)
    merge.Add(RepairKind::kOverlapLeft, first_facet[left.first_facet], -1, left.at,
              absl::StrCat("bodies exported overlapping, not united: ", left.reason));
  for (const UnitedBodies& b : u.united)
    merge.Add(RepairKind::kUnitedBodies, first_facet[b.first_facet], -1, b.at,
              absl::StrFormat("%u bodies exported overlapping united: their %u facets re-made as "
                              "%u, %u points added where their surfaces cross; volume %.6g "
                              "(the bodies' summed, the overlap counted twice) -> %.6g",
                              b.bodies, b.facets_before, b.facets_after, b.points_added,
                              b.volume_before, b.volume_after));
  if (u.united.empty()) {
    SortRecords(repaired.report);
    return repaired;
  }
  FoldRecheck(repaired, *std::move(checked), u.facet_origin, u.vertex_origin, mesh, merge);
  return repaired;
}

}  // namespace femsimp
