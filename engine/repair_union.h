// The union step of the repair (RepairOptions::unite_overlaps): unites the bodies that cross each
// other (engine/overlap_union.h) in a mesh the other repairs have made, checks the result with
// them again, and reports both in the input's numbering.
#pragma once

#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"
#include "engine/repair.h"

namespace femsimp {

// `mesh` as RepairMesh left it, `repaired` what it said; returns the report with the united
// bodies (and those left overlapping) added and the seams, provenance and counts of the result.
absl::StatusOr<RepairResult> UniteRepaired(RawMesh& mesh, const RepairOptions& options,
                                           RepairResult repaired);

}  // namespace femsimp
