// The FE check's external tools (tetgen, ccx) run as child processes: found on PATH, started in
// a working directory with their output in a log file, in a process group of their own so that a
// cancel kills them and whatever they started, and never left behind as zombies.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace femsimp::fecheck {

// The executable `program` in the first directory of `path_list` (a PATH value) that holds it;
// NotFound when none does.
absl::StatusOr<std::string> FindOnPath(absl::string_view program, absl::string_view path_list);

struct ChildRun {
  std::string command = "";              // the tool's name, for messages
  std::vector<std::string> argv = {};    // argv[0]: the executable's path
  std::string dir = "";                  // working directory
  std::string log_path = "";             // stdout and stderr go here
  std::vector<std::string> env = {};     // NAME=VALUE set on top of this process's environment
  std::function<bool()> cancelled = {};  // polled while the child runs; true kills it
};

struct ChildExit {
  int exit_code = -1;  // when it exited
  int signal = 0;      // when a signal ended it
  bool ok() const { return signal == 0 && exit_code == 0; }
  std::string Describe() const;  // "exit code 201", "killed by signal 6 (Aborted)"
};

// Starts the child and waits for it, polling `cancelled` every 10 ms. Cancelled (after killing
// its process group and reaping it) when `cancelled` said so; Internal when it could not start.
absl::StatusOr<ChildExit> RunChild(const ChildRun& run);

// The last `lines` non-empty lines of a text file ("" if it cannot be read).
std::string LastLines(const std::string& path, int lines);
// The first `lines` lines of the file that contain `part`, trimmed ("" if none).
std::string MatchingLines(const std::string& path, absl::string_view part, int lines);

}  // namespace femsimp::fecheck
