// What the repair steps that rewrite a repaired mesh (the imprint, engine/repair_imprint.h; taking
// out crossing facets, engine/repair_uncross.h; the union, engine/repair_union.h) share: their
// records in the input's numbering, and the other repairs run again on what they made, judged
// and folded into the report of the first run.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "absl/functional/function_ref.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "engine/raw_mesh.h"
#include "engine/repair.h"

namespace femsimp {

// A point a step added (no vertex of the mesh it was given).
inline constexpr uint32_t kNoStepVertex = std::numeric_limits<uint32_t>::max();

// Adds records to a repair result, each kind up to the cap of records listed.
class ReportMerger {
 public:
  ReportMerger(RepairResult& result, const RawMesh& mesh, size_t max_records_per_kind);

  // Counts and lists one record; `at` relative to the mesh's origin.
  void Add(RepairKind kind, int64_t facet, int64_t vertex, const std::array<double, 3>& at,
           std::string detail);
  // A record whose count is already in the report (`at` in the file's coordinates).
  void Keep(RepairRecord record);
  void DropRecords(RepairKind kind);
  std::array<double, 3> World(const std::array<double, 3>& p) const;

 private:
  RepairResult& result_;
  const RawMesh& mesh_;
  const size_t cap_;
  std::array<size_t, kNumRepairKinds> listed_{};
};

// Folds `checked`, the repairs run again on `mesh` (what a step made of the repaired mesh), into
// `repaired`, the first run's result: counts of changes add up, the defects the repairs leave in
// place (seams, non-orientable components, folds and holes left) are the second run's; records,
// seams and provenance are renumbered
// to the input's facets and vertices through the step's (facet f of the step's result came from
// facet step_facet_origin[f] of the repaired mesh; vertices likewise, kNoStepVertex for a point
// the step added). Records end sorted by kind, facet and vertex.
void FoldRecheck(RepairResult& repaired, RepairResult checked,
                 const std::vector<uint32_t>& step_facet_origin,
                 const std::vector<uint32_t>& step_vertex_origin, const RawMesh& mesh,
                 ReportMerger& merge);

// Why a step's result is refused after the repairs ran again on it: the recheck's error, or
// "`what` (kind)" for the first kind it counted more of than `allowed(kind)`; empty when neither.
std::string RecheckObjection(const absl::StatusOr<RepairResult>& checked,
                             absl::FunctionRef<size_t(RepairKind)> allowed, absl::string_view what);

// Sorts the records by kind, then facet, then vertex: how reports list them.
void SortRecords(RepairReport& report);

}  // namespace femsimp
