// `femsimp simplify ... --server HOST:PORT`: the same job run on a femsimp-server.
#pragma once

#include "client/args.h"

namespace femsimp::cli {

// Returns the process exit code (exit_codes.h): kExitGrpcBase + code for gRPC errors.
int RunRemote(const SimplifyArgs& args);

}  // namespace femsimp::cli
