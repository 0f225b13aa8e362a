#include "client/remote_run.h"

#include <cstdio>

#include "client/exit_codes.h"

namespace femsimp::cli {

int RunRemote(const SimplifyArgs&) {
  std::fprintf(stderr, "femsimp: remote mode not written yet\n");
  return kExitInternal;
}

}  // namespace femsimp::cli
