// The two programs the FE check drives, found on PATH, and how one of their runs is reported:
// a missing program names its Debian package, a failed run quotes the program's last lines.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fecheck/child_process.h"

namespace femsimp::fecheck {

struct Tool {
  const char* program;
  const char* debian_package;
  const char* what;  // for progress lines and messages
};
inline constexpr Tool kTetgen{"tetgen", "tetgen", "tetgen (tetrahedral mesh)"};
inline constexpr Tool kCalculix{"ccx", "calculix-ccx", "CalculiX (modal analysis)"};

// The program's path on $PATH; NotFound naming the Debian package that provides it otherwise.
absl::StatusOr<std::string> LocateTool(const Tool& tool);
// Both tools, or NotFound naming every missing one and its package.
absl::Status LocateTools();

// Where and how a tool runs.
struct ToolRun {
  std::string dir = "";                  // working directory (a TempDir)
  std::function<bool()> cancelled = {};  // polled while it runs
  int threads = 1;                       // OMP_NUM_THREADS of the run
};

// Runs the tool with `args` in run.dir, its output in run.dir/<program>.log; the exit, or
// Cancelled / NotFound / Internal (could not start).
struct ToolExit {
  ChildExit exit;
  std::string log_path;
};
absl::StatusOr<ToolExit> RunTool(const Tool& tool, const std::vector<std::string>& args,
                                 const ToolRun& run);

// "tetgen failed (exit code 1); its last lines:\n  ..." plus `why` when given.
std::string ToolFailure(const Tool& tool, const ToolExit& exit, const std::string& why = "");

}  // namespace femsimp::fecheck
