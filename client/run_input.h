// The start shared by the local and the remote simplify run: the report skeleton, the input
// file, the clock.
#pragma once

#include <chrono>
#include <optional>

#include "client/args.h"
#include "client/report.h"
#include "engine/raw_mesh.h"

namespace femsimp::cli {

RunReport StartReport(const SimplifyArgs& args);

// Reads args.input and records its vertex and face counts; on failure prints the reason on
// stderr and returns nullopt (the caller exits with kExitInputUnreadable).
std::optional<RawMesh> ReadInput(const SimplifyArgs& args, RunReport& report);

double SecondsSince(std::chrono::steady_clock::time_point t0);

}  // namespace femsimp::cli
