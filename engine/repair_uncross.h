// The repair step that takes out facets of a surface crossing each other (engine/crossing_repair.h)
// in a mesh the other repairs have made, checks the result with them again, and reports both in
// the input's numbering.
#pragma once

#include "absl/status/statusor.h"
#include "engine/crossing_repair.h"
#include "engine/raw_mesh.h"
#include "engine/repair.h"

namespace femsimp {

// `mesh` as RepairMesh left it, `repaired` what it said; returns the report with the patches
// taken out (kCrossingRemoved) and the crossings left (kCrossingLeft) added, and the seams,
// provenance and counts of the result. Where the result would need what no repair fixes, the
// mesh stays as it was and its crossings are reported as left. With CrossingScope::kWithinSurfaces
// (a pass before the union) nothing is reported left: the pass after the union does that.
absl::StatusOr<RepairResult> UncrossRepaired(RawMesh& mesh, const RepairOptions& options,
                                             RepairResult repaired,
                                             CrossingScope scope = CrossingScope::kAll);

}  // namespace femsimp
