#include "engine/repair_imprint.h"

#include <algorithm>
#include <tuple>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/imprint.h"

namespace femsimp {
namespace {

class ReportMerger {
 public:
  ReportMerger(RepairResult& result, const RawMesh& mesh, size_t max_records_per_kind)
      : result_(result), mesh_(mesh), cap_(max_records_per_kind) {
    for (const RepairRecord& r : result.report.records) ++listed_[static_cast<size_t>(r.kind)];
  }

  void Add(RepairKind kind, int64_t facet, int64_t vertex, const std::array<double, 3>& at,
           std::string detail) {
    ++result_.report.counts[static_cast<size_t>(kind)];
    Keep({kind, facet, vertex, World(at), std::move(detail)});
  }
  // A record whose count is already in the report.
  void Keep(RepairRecord record) {
    size_t& listed = listed_[static_cast<size_t>(record.kind)];
    if (listed >= cap_) return;
    ++listed;
    result_.report.records.push_back(std::move(record));
  }
  void DropRecords(RepairKind kind) {
    std::erase_if(result_.report.records, [&](const RepairRecord& r) { return r.kind == kind; });
    listed_[static_cast<size_t>(kind)] = 0;
  }
  std::array<double, 3> World(const std::array<double, 3>& p) const {
    return {mesh_.origin[0] + p[0], mesh_.origin[1] + p[1], mesh_.origin[2] + p[2]};
  }

 private:
  RepairResult& result_;
  const RawMesh& mesh_;
  const size_t cap_;
  std::array<size_t, kNumRepairKinds> listed_{};
};

}  // namespace

absl::StatusOr<RepairResult> ImprintRepaired(RawMesh& mesh, const RepairOptions& options,
                                             RepairResult repaired) {
  RawMesh unimprinted = mesh;  // what stays should the result need what no repair fixes
  ImprintResult imprint = ImprintContacts(mesh);
  // The other repairs again, on the imprinted mesh: its seams, and whatever the re-tiling left
  // for them (two points where edges cross closer than the weld tolerance, a needle). Should
  // they fail or leave a defect, the contacts stay as exported.
  RepairOptions again = options;
  again.imprint = false;
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
  RepairReport& report = repaired.report;
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
    std::sort(report.records.begin(), report.records.end(),
              [](const RepairRecord& a, const RepairRecord& b) {
                return std::tie(a.kind, a.facet, a.vertex) < std::tie(b.kind, b.facet, b.vertex);
              });
    return repaired;
  }

  const auto input_facet = [&](int64_t f) -> int64_t {
    return f < 0 ? f : first_facet[imprint.facet_origin[f]];
  };
  const auto input_vertex = [&](int64_t v) -> int64_t {
    if (v < 0 || imprint.vertex_origin[v] == kNoSourceVertex) return -1;
    return first_vertex[imprint.vertex_origin[v]];
  };
  merge.DropRecords(RepairKind::kSeamEdge);
  report.counts[static_cast<size_t>(RepairKind::kSeamEdge)] = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k) report.counts[k] += checked->report.counts[k];
  for (RepairRecord& r : checked->report.records) {
    if (r.kind == RepairKind::kSeamEdge) continue;  // listed again below, in input facets
    r.facet = input_facet(r.facet);
    r.vertex = input_vertex(r.vertex);
    merge.Keep(std::move(r));
  }
  repaired.seams = std::move(checked->seams);
  std::vector<size_t> seam_faces;  // before pieces of one input facet are listed once
  for (SeamEdge& seam : repaired.seams) {
    seam_faces.push_back(seam.facets.size());
    for (uint32_t& f : seam.facets) f = uint32_t(input_facet(f));
    std::sort(seam.facets.begin(), seam.facets.end());
    seam.facets.erase(std::unique(seam.facets.begin(), seam.facets.end()), seam.facets.end());
  }
  repaired.facet_origin.resize(checked->facet_origin.size());
  for (size_t f = 0; f < checked->facet_origin.size(); ++f)
    repaired.facet_origin[f] = uint32_t(input_facet(checked->facet_origin[f]));
  repaired.vertex_origin.resize(checked->vertex_origin.size());
  for (size_t v = 0; v < checked->vertex_origin.size(); ++v) {
    const int64_t input = input_vertex(checked->vertex_origin[v]);
    repaired.vertex_origin[v] = input < 0 ? kNoInputVertex : uint32_t(input);
  }
  for (size_t i = 0; i < repaired.seams.size(); ++i) {
    const SeamEdge& seam = repaired.seams[i];
    const uint32_t from = repaired.vertex_origin[seam.a];
    const auto world = [&](const std::array<float, 3>& p) {
      return merge.World({p[0], p[1], p[2]});
    };
    merge.Keep({RepairKind::kSeamEdge, seam.facets[0],
                from == kNoInputVertex ? int64_t{-1} : int64_t{from}, world(seam.pa),
                SeamDetail(world(seam.pb), seam_faces[i], seam.facets)});
  }
  std::sort(report.records.begin(), report.records.end(),
            [](const RepairRecord& a, const RepairRecord& b) {
              return std::tie(a.kind, a.facet, a.vertex) < std::tie(b.kind, b.facet, b.vertex);
            });
  report.output_vertices = mesh.num_vertices();
  report.output_facets = mesh.num_faces();
  return repaired;
}

}  // namespace femsimp
