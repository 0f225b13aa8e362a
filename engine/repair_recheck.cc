#include "engine/repair_recheck.h"

#include <algorithm>
#include <tuple>
#include <utility>

#include "absl/strings/str_cat.h"

namespace femsimp {

ReportMerger::ReportMerger(RepairResult& result, const RawMesh& mesh, size_t max_records_per_kind)
    : result_(result), mesh_(mesh), cap_(max_records_per_kind) {
  for (const RepairRecord& r : result.report.records) ++listed_[static_cast<size_t>(r.kind)];
}

void ReportMerger::Add(RepairKind kind, int64_t facet, int64_t vertex,
                       const std::array<double, 3>& at, std::string detail) {
  ++result_.report.counts[static_cast<size_t>(kind)];
  Keep({kind, facet, vertex, World(at), std::move(detail)});
}

void ReportMerger::Keep(RepairRecord record) {
  size_t& listed = listed_[static_cast<size_t>(record.kind)];
  if (listed >= cap_) return;
  ++listed;
  result_.report.records.push_back(std::move(record));
}

void ReportMerger::DropRecords(RepairKind kind) {
  std::erase_if(result_.report.records, [&](const RepairRecord& r) { return r.kind == kind; });
  listed_[static_cast<size_t>(kind)] = 0;
}

std::array<double, 3> ReportMerger::World(const std::array<double, 3>& p) const {
  return {mesh_.origin[0] + p[0], mesh_.origin[1] + p[1], mesh_.origin[2] + p[2]};
}

std::string RecheckObjection(const absl::StatusOr<RepairResult>& checked,
                             absl::FunctionRef<size_t(RepairKind)> allowed,
                             absl::string_view what) {
  if (!checked.ok()) return std::string(checked.status().message());
  for (size_t k = 0; k < kNumRepairKinds; ++k) {
    const auto kind = static_cast<RepairKind>(k);
    if (checked->report.count(kind) > allowed(kind))
      return absl::StrCat(what, " (", RepairKindName(kind), ")");
  }
  return "";
}

void SortRecords(RepairReport& report) {
  std::sort(report.records.begin(), report.records.end(),
            [](const RepairRecord& a, const RepairRecord& b) {
              return std::tie(a.kind, a.facet, a.vertex) < std::tie(b.kind, b.facet, b.vertex);
            });
}

void FoldRecheck(RepairResult& repaired, RepairResult checked,
                 const std::vector<uint32_t>& step_facet_origin,
                 const std::vector<uint32_t>& step_vertex_origin, const RawMesh& mesh,
                 ReportMerger& merge) {
  RepairReport& report = repaired.report;
  const std::vector<uint32_t> first_facet = repaired.facet_origin;
  const std::vector<uint32_t> first_vertex = repaired.vertex_origin;
  const auto input_facet = [&](int64_t f) -> int64_t {
    return f < 0 ? f : first_facet[step_facet_origin[f]];
  };
  const auto input_vertex = [&](int64_t v) -> int64_t {
    if (v < 0 || step_vertex_origin[v] == kNoStepVertex) return -1;
    return first_vertex[step_vertex_origin[v]];
  };
  // What the repairs leave in place they find again in the step's result: that view replaces
  // the first run's (seams are listed again below, in input facets).
  for (RepairKind kind : {RepairKind::kSeamEdge, RepairKind::kNonOrientable, RepairKind::kFoldLeft,
                          RepairKind::kHoleLeft}) {
    merge.DropRecords(kind);
    report.counts[static_cast<size_t>(kind)] = 0;
  }
  for (size_t k = 0; k < kNumRepairKinds; ++k) report.counts[k] += checked.report.counts[k];
  for (RepairRecord& r : checked.report.records) {
    if (r.kind == RepairKind::kSeamEdge) continue;  // listed again below, in input facets
    r.facet = input_facet(r.facet);
    r.vertex = input_vertex(r.vertex);
    merge.Keep(std::move(r));
  }
  repaired.seams = std::move(checked.seams);
  std::vector<size_t> seam_faces;  // before pieces of one input facet are listed once
  for (SeamEdge& seam : repaired.seams) {
    seam_faces.push_back(seam.facets.size());
    for (uint32_t& f : seam.facets) f = uint32_t(input_facet(f));
    std::sort(seam.facets.begin(), seam.facets.end());
    seam.facets.erase(std::unique(seam.facets.begin(), seam.facets.end()), seam.facets.end());
  }
  repaired.facet_origin.resize(checked.facet_origin.size());
  for (size_t f = 0; f < checked.facet_origin.size(); ++f)
    repaired.facet_origin[f] = uint32_t(input_facet(checked.facet_origin[f]));
  repaired.vertex_origin.resize(checked.vertex_origin.size());
  for (size_t v = 0; v < checked.vertex_origin.size(); ++v) {
    const int64_t input = input_vertex(checked.vertex_origin[v]);
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
  SortRecords(report);
  report.output_vertices = mesh.num_vertices();
  report.output_facets = mesh.num_faces();
}

}  // namespace femsimp
