// `femsimp check ORIGINAL SIMPLIFIED`: the FE check of two mesh files (fecheck/fe_check.h):
// both read and repaired as `simplify` does, tet-meshed, analysed, and compared.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fecheck/fe_check.h"

namespace femsimp::cli {

struct CheckArgs {
  std::string original, simplified;
  fecheck::FeCheckOptions options;
  std::string json;  // empty: no JSON file
  bool quiet = false;
  bool help = false;
};

std::string CheckUsage();
// The arguments after "check". Errors are usage errors naming the flag.
absl::StatusOr<CheckArgs> ParseCheckArgs(const std::vector<std::string>& args);
// Runs the check and prints it; returns the exit code (exit_codes.h).
int RunCheck(const CheckArgs& args);

}  // namespace femsimp::cli
