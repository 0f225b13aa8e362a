// What femsimp prints of an FE check (femsimp check, simplify --fe-check, locally or from the
// server's Result): the table on stdout, the JSON document, the progress on stderr, and the
// exit code of a failed check.
#pragma once

#include <array>
#include <atomic>
#include <string>

#include "absl/status/status.h"
#include "fecheck/fe_check.h"

namespace femsimp::cli {

// Both meshes side by side with their relative differences; `names` head the columns' note.
std::string FeCheckTable(const fecheck::FeCheckReport& report,
                         const std::array<std::string, 2>& paths);
// {"material": ..., "unit_scale": ..., "original": {...}, "simplified": {...},
//  "differences": {...}}; paths may be empty (then no "path" member).
std::string FeCheckJson(const fecheck::FeCheckReport& report,
                        const std::array<std::string, 2>& paths, int indent = 0);

// Progress on stderr: a bar redrawn in place on a terminal, one line per step otherwise;
// nothing when quiet. `interrupted` (Ctrl-C) cancels the running tool.
fecheck::FeCheckControl TerminalFeControl(bool quiet, const std::atomic<bool>* interrupted);

// kExitToolMissing (NotFound), kExitInputInvalid (the surface cannot be checked),
// kExitCancelled, kExitEngineFailed (the analysis failed).
int FeCheckExitCode(const absl::Status& status);

}  // namespace femsimp::cli
