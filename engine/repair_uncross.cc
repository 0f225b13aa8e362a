#include "engine/repair_uncross.h"

#include <cstdint>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/crossing_repair.h"
#include "engine/repair_recheck.h"

namespace femsimp {

absl::StatusOr<RepairResult> UncrossRepaired(RawMesh& mesh, const RepairOptions& options,
                                             RepairResult repaired, CrossingScope scope) {
  const size_t given_vertices = mesh.num_vertices();
  UncrossResult uncross = TakeOutCrossings(mesh, options.threads, scope);
  // The other repairs again, on a copy made only where something was taken out: they drop the
  // vertices taken out and check that the closed rims left nothing for them (an edge used three
  // times, a component turned). Should they, the mesh stays as it was.
  RepairOptions again = options;
  again.take_out_crossings = false;
  again.imprint = false;
  again.unite_overlaps = false;
  absl::StatusOr<RepairResult> checked = absl::InternalError("not run");
  if (!uncross.facet_origin.empty()) {
    RawMesh next = std::move(uncross.mesh);
    checked = RepairMesh(next, again);
    // Only the vertices the patches used may go; any other change, or a defect more than the
    // first run left, would be the fills' doing.
    const std::string why = RecheckObjection(
        checked,
        [&](RepairKind kind) -> size_t {
          return kind == RepairKind::kUnreferencedVertex ? SIZE_MAX
                 : IsRepairChange(kind)                  ? 0
                                                         : repaired.report.count(kind);
        },
        "the closed rims would need a repair of their own");
    if (why.empty()) {
      mesh = std::move(next);
    } else {
      uncross.left.clear();
      for (const UncrossedPatch& p : uncross.patches)
        uncross.left.push_back({p.first_facet, p.at,
                                absl::StrCat("facets of one surface cross each other; not taken "
                                             "out: ",
                                             why)});
      uncross.patches.clear();
      uncross.facet_origin.clear();
    }
  }
  if (scope == CrossingScope::kWithinSurfaces) uncross.left.clear();
  ReportMerger merge(repaired, mesh, options.max_records_per_kind);
  const std::vector<uint32_t>& first_facet = repaired.facet_origin;
  for (const CrossingLeft& left : uncross.left)
    merge.Add(RepairKind::kCrossingLeft, first_facet[left.first_facet], -1, left.at, left.reason);
  for (const UncrossedPatch& p : uncross.patches)
    merge.Add(
        RepairKind::kCrossingRemoved, first_facet[p.first_facet], -1, p.at,
        absl::StrFormat(
            "facets of one surface crossed each other: %u facets around them taken out%s "
            "and their rim of %u edges (%.6g across: where the vertex belonged is lost) closed "
            "by %u facets; area %.6g -> %.6g, enclosed volume changed by %.6g",
            p.facets_removed,
            p.vertices_dropped == 0
                ? std::string()
                : absl::StrFormat(" (%u %s with them, the farthest %.6g off the new facets)",
                                  p.vertices_dropped,
                                  p.vertices_dropped == 1 ? "vertex" : "vertices", p.farthest),
            p.loop_edges, p.across, p.facets_added, p.area_removed, p.area_added, p.volume_change));
  if (uncross.facet_origin.empty()) {
    SortRecords(repaired.report);
    return repaired;
  }
  std::vector<uint32_t> same_vertex(given_vertices);
  std::iota(same_vertex.begin(), same_vertex.end(), 0u);
  FoldRecheck(repaired, *std::move(checked), uncross.facet_origin, same_vertex, mesh, merge);
  return repaired;
}

}  // namespace femsimp
