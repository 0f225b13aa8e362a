// The imprint step of the repair (RepairOptions::imprint): re-tiles the contacts of bodies
// exported apart (engine/imprint.h) in a mesh the other repairs have made, checks the result
// with them again, and reports both in the input's numbering.
#pragma once

#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"
#include "engine/repair.h"

namespace femsimp {

// `mesh` as RepairMesh left it, `repaired` what it said; returns the report with the imprinted
// contacts (and those left apart) added and the seams, provenance and counts of the result.
absl::StatusOr<RepairResult> ImprintRepaired(RawMesh& mesh, const RepairOptions& options,
                                             RepairResult repaired);

}  // namespace femsimp
