#include "fecheck/tools.h"

#include <cstdlib>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_replace.h"

namespace femsimp::fecheck {
namespace {

constexpr int kQuotedLines = 8;

std::string PathList() {
  const char* path = std::getenv("PATH");
  return path == nullptr ? "" : path;
}

}  // namespace

absl::StatusOr<std::string> LocateTool(const Tool& tool) {
  absl::StatusOr<std::string> found = FindOnPath(tool.program, PathList());
  if (found.ok()) return found;
  return absl::NotFoundError(absl::StrCat(tool.program,
                                          " not found on PATH: install the Debian package ",
                                          tool.debian_package, " (scripts/install-deps.sh)"));
}

absl::Status LocateTools() {
  std::vector<std::string> missing;
  for (const Tool& tool : {kTetgen, kCalculix})
    if (!LocateTool(tool).ok())
      missing.push_back(absl::StrCat(tool.program, " (Debian package ", tool.debian_package, ")"));
  if (missing.empty()) return absl::OkStatus();
  return absl::NotFoundError(absl::StrCat(
      "the FE check needs tetgen and CalculiX; not found on PATH: ", absl::StrJoin(missing, ", "),
      " (apt-get install tetgen calculix-ccx, or scripts/install-deps.sh)"));
}

absl::StatusOr<ToolExit> RunTool(const Tool& tool, const std::vector<std::string>& args,
                                 const ToolRun& run) {
  absl::StatusOr<std::string> program = LocateTool(tool);
  if (!program.ok()) return program.status();
  ChildRun child;
  child.command = tool.program;
  // Killed when the thread that started it dies (util-linux's setpriv), so that a femsimp or a
  // server killed outright leaves no solver running; line-buffered through coreutils' stdbuf, so
  // that what a tool said before it aborted is in its log. Each where there is one.
  if (absl::StatusOr<std::string> setpriv = FindOnPath("setpriv", PathList()); setpriv.ok())
    child.argv = {*setpriv, "--pdeathsig", "KILL"};
  if (absl::StatusOr<std::string> stdbuf = FindOnPath("stdbuf", PathList()); stdbuf.ok())
    child.argv.insert(child.argv.end(), {*stdbuf, "-oL", "-eL"});
  child.argv.push_back(*program);
  child.argv.insert(child.argv.end(), args.begin(), args.end());
  child.dir = run.dir;
  ToolExit out;
  out.log_path = absl::StrCat(run.dir, "/", tool.program, ".log");
  child.log_path = out.log_path;
  child.env = {absl::StrCat("OMP_NUM_THREADS=", run.threads)};
  child.cancelled = run.cancelled;
  absl::StatusOr<ChildExit> exit = RunChild(child);
  if (!exit.ok()) return exit.status();
  out.exit = *exit;
  return out;
}

std::string ToolFailure(const Tool& tool, const ToolExit& exit, const std::string& why) {
  std::string tail = LastLines(exit.log_path, kQuotedLines);
  // ccx says what went wrong in "*ERROR ..." lines that need not be among the last ones.
  const std::string errors = MatchingLines(exit.log_path, "*ERROR", kQuotedLines);
  if (!errors.empty() && tail.find(errors) == std::string::npos)
    tail = absl::StrCat(errors, "\n...\n", tail);
  return absl::StrCat(tool.program, " failed (", why.empty() ? exit.exit.Describe() : why, ")",
                      tail.empty() ? "; it printed nothing"
                                   : absl::StrCat("; its last lines:\n    ",
                                                  absl::StrReplaceAll(tail, {{"\n", "\n    "}})));
}

}  // namespace femsimp::fecheck
