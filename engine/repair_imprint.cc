#include "engine/repair_imprint.h"

#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/imprint.h"
#include "engine/repair_recheck.h"

namespace femsimp {

static_assert(kNoSourceVertex == kNoStepVertex);

absl::StatusOr<RepairResult> ImprintRepaired(RawMesh& mesh, const RepairOptions& options,
                                             RepairResult repaired) {
  RawMesh unimprinted = mesh;  // what stays should the result need what no repair fixes
  ImprintResult imprint = ImprintContacts(mesh);
  // The other repairs again, on the imprinted mesh: its seams, and whatever the re-tiling left
  // for them (two points where edges cross closer than the weld tolerance, a needle). Should
  // they fail or leave a defect, the contacts stay as exported.
  RepairOptions again = options;
  again.imprint = false;
  again.take_out_crossings = false;  // the imprint's rounds have looked for them
  again.unite_overlaps = false;
  absl::StatusOr<RepairResult> checked = absl::InternalError("not run");
  if (!imprint.contacts.empty()) {
    checked = RepairMesh(mesh, again);
    const size_t left_before = repaired.report.count(RepairKind::kNonOrientable);
    if (!checked.ok() || checked->report.count(RepairKind::kNonOrientable) > left_before) {
      const std::string why =
          checked.ok() ? "the re-tiled mesh has a component no orientation makes consistent"
                       : std::string(checked.status().message());
      mesh = std::move(unimprinted);
      for (const ImprintedContact& c : imprint.contacts)
        imprint.left.push_back({c.first_facet, c.at, absl::StrCat("after the re-tiling: ", why)});
      imprint.contacts.clear();
    }
  }
  ReportMerger merge(repaired, mesh, options.max_records_per_kind);
  const std::vector<uint32_t> first_facet = repaired.facet_origin;
  const std::vector<uint32_t> first_vertex = repaired.vertex_origin;
  for (const ContactLeft& left : imprint.left)
    merge.Add(RepairKind::kContactLeft, first_facet[left.first_facet], -1, left.at,
              absl::StrCat("not imprinted: ", left.reason));
  for (const ImprintedContact& c : imprint.contacts)
    merge.Add(RepairKind::kImprintedContact, first_facet[c.first_facet], -1, c.at,
              absl::StrFormat("bodies exported apart touch over an area of %.6g: %u facets of the "
                              "two re-tiled as %u, %u of them shared by both; %u points added "
                              "where their edges cross, %u corners of one taken as the other's",
                              c.area, c.facets_before, c.facets_after, c.shared_facets,
                              c.points_added, c.corners_merged));
  if (imprint.contacts.empty()) {
    SortRecords(repaired.report);
    return repaired;
  }

  FoldRecheck(repaired, *std::move(checked), imprint.facet_origin, imprint.vertex_origin, mesh,
              merge);
  return repaired;
}

}  // namespace femsimp
