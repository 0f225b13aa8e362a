#include "engine/prepare.h"

#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace femsimp {
namespace {

// How many seams and other leftover defects an error names one by one (the message goes into a
// gRPC status too, whose size is bounded).
constexpr size_t kMaxListed = 20;

std::string PointText(const std::array<float, 3>& p) {
  return absl::StrFormat("(%g, %g, %g)", p[0], p[1], p[2]);
}

absl::Status SeamsNotSupported(const std::vector<SeamEdge>& seams) {
  std::vector<std::string> listed;
  for (size_t i = 0; i < seams.size() && i < kMaxListed; ++i)
    listed.push_back(absl::StrCat("edge ", PointText(seams[i].pa), " - ", PointText(seams[i].pb),
                                  " shared by facets ", absl::StrJoin(seams[i].facets, ", ")));
  if (seams.size() > kMaxListed)
    listed.push_back(absl::StrCat("and ", seams.size() - kMaxListed, " more"));
  return absl::InvalidArgumentError(absl::StrCat(
      "the mesh has ", seams.size(), " non-manifold edge", seams.size() == 1 ? "" : "s",
      " (shared by 3 or more facets, e.g. parts of an assembly sharing a face); non-manifold "
      "seams are not supported yet: ",
      absl::StrJoin(listed, "; ")));
}

// Defects the repair leaves in place other than seams (a non-orientable component), named by
// their records.
absl::Status DefectsLeft(const RepairReport& report) {
  std::vector<std::string> listed;
  for (const RepairRecord& r : report.records)
    if (!IsRepairChange(r.kind) && r.kind != RepairKind::kSeamEdge) listed.push_back(r.ToString());
  return absl::InvalidArgumentError(
      absl::StrCat("the mesh has defects no repair fixes: ", absl::StrJoin(listed, "; ")));
}

}  // namespace

absl::StatusOr<PreparedMesh> PrepareMesh(RawMesh raw, const RepairOptions& options) {
  absl::StatusOr<RepairResult> repaired = RepairMesh(raw, options);
  if (!repaired.ok()) return repaired.status();
  if (repaired->report.num_defects_left() > repaired->report.count(RepairKind::kSeamEdge))
    return DefectsLeft(repaired->report);

  // HOOK (locked seams): this is the one place where a mesh with seams would be split along
  // repaired->seams into manifold pieces before Mesh::Build, and the pieces' seam vertices
  // locked and rejoined after the simplification. Until then a seam is refused here.
  if (!repaired->seams.empty()) return SeamsNotSupported(repaired->seams);

  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  if (!mesh.ok()) return mesh.status();
  return PreparedMesh{*std::move(mesh), std::move(repaired->report), std::move(repaired->seams)};
}

}  // namespace femsimp
