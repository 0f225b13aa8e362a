// femsimp: the command-line program (local simplification, or remote with --server).
#include <cstdio>
#include <new>
#include <string>
#include <vector>

#include "client/args.h"
#include "client/exit_codes.h"
#include "client/local_run.h"
#include "common/escape.h"
#ifdef FEMSIMP_HAVE_REMOTE
#include "client/health.h"
#include "client/remote_run.h"
#endif

int main(int argc, char** argv) {
  using namespace femsimp::cli;
  std::vector<std::string> args(argv, argv + argc);
  if (args.size() >= 2 && args[1] == "health") {
#ifdef FEMSIMP_HAVE_REMOTE
    return RunHealth(std::vector<std::string>(args.begin() + 2, args.end()));
#else
    femsimp::PrintError("femsimp: this build has no gRPC client (FEMSIMP_BUILD_SERVICE=OFF)\n");
    return kExitUsage;
#endif
  }
  absl::StatusOr<Command> cmd = ParseCommandLine(args);
  if (!cmd.ok()) {
    femsimp::PrintError("femsimp: %s\n", std::string(cmd.status().message()).c_str());
    return kExitUsage;
  }
  if (cmd->kind == Command::kHelp) {
    std::fputs(cmd->help_text.c_str(), stdout);
    return kExitOk;
  }
  if (cmd->kind == Command::kCheck) return RunCheck(cmd->check);
  const SimplifyArgs& s = cmd->simplify;
  if (!s.server.empty()) {
#ifdef FEMSIMP_HAVE_REMOTE
    return RunRemote(s);
#else
    femsimp::PrintError("femsimp: this build has no gRPC client (FEMSIMP_BUILD_SERVICE=OFF)\n");
    return kExitUsage;
#endif
  }
  try {
    return RunLocal(s);
  } catch (const std::bad_alloc&) {
    femsimp::PrintError("femsimp: not enough memory to simplify %s locally\n", s.input.c_str());
    return kExitEngineFailed;
  }
}
