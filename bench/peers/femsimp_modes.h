// femsimp's modes in the fidelity table (bench/fidelity_table.cc): each a name and a set of
// engine options written as femsimp simplify's flags, so that a new engine option or preset is
// one more mode on the command line, not new code.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "bench/peers/peer_run.h"
#include "engine/simplify.h"

namespace femsimp::bench {

struct FemsimpMode {
  std::string name;   // the table's tool column: "femsimp <name>"
  std::string flags;  // as given, e.g. "--preset paper --min-angle 0"
  SimplifyOptions options;
  bool threads_given = false;  // else the table's --threads applies
};

// "NAME=FLAGS": FLAGS are femsimp simplify's engine option flags (`femsimp options`), split at
// blanks, a preset first applied wherever it stands (as the CLI does). The table sets the
// tolerance itself, so --tolerance and --tolerance-relative are refused here.
absl::StatusOr<FemsimpMode> ParseFemsimpMode(const std::string& spec);

// The modes the table runs unless told otherwise: the `fe` preset (a plain call with the
// tolerance) and "bound only" (the tolerance, topology, no self-intersection, feature lines; the
// volume, angle and normal criteria off), each with the deviation and the quadric order, and
// bound only without feature lines.
std::vector<std::string> DefaultFemsimpModes();

// The mode's options with tolerance_relative set, on the input prepared as the CLI prepares it
// (PrepareMesh: repair, spatial renumbering, build), which is not timed (the peers' mesh set-up
// is not either): seconds are the engine's own. The output as the CLI writes it (OutputMesh).
PeerRun RunFemsimp(const RawMesh& input, SimplifyOptions options);

}  // namespace femsimp::bench
