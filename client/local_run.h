// `femsimp simplify` in-process: read, validate, simplify, write, report.
#pragma once

#include "client/args.h"

namespace femsimp::cli {

// Returns the process exit code (exit_codes.h); messages go to stderr, the table to stdout.
int RunLocal(const SimplifyArgs& args);

}  // namespace femsimp::cli
