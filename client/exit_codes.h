// Exit codes of the femsimp and femsimp-load programs; documented in --help (args.cc).
#pragma once

namespace femsimp::cli {

enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,         // unexpected failure inside the client
  kExitUsage = 2,            // unknown flag, missing or non-numeric value, value out of range
  kExitInputUnreadable = 3,  // input file missing, unreadable or not a parsable mesh file
  kExitInputInvalid = 4,     // the mesh cannot be prepared (PrepareMesh: repair, validation)
  kExitOutputFailed = 5,     // output mesh or --stats-json could not be written
  kExitEngineFailed = 6,     // the simplification itself failed
  kExitCancelled = 7,        // interrupted (SIGINT) in local mode
  kExitNotServing = 8,       // health: the server answered but is not SERVING
  kExitToolMissing = 9,      // check, --fe-check: tetgen or ccx (CalculiX) is not on the PATH
  // Remote mode: a gRPC status other than OK exits with kExitGrpcBase + its code
  // (CANCELLED 21, UNKNOWN 22, INVALID_ARGUMENT 23, DEADLINE_EXCEEDED 24, ..., UNAVAILABLE 34).
  kExitGrpcBase = 20,
};

}  // namespace femsimp::cli
