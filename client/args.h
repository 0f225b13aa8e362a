// Command-line parsing of `femsimp simplify`, shared by the local and the remote mode.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "client/check_cmd.h"
#include "client/security_flags.h"
#include "common/flags.h"
#include "engine/simplify.h"
#include "fecheck/fe_check.h"

namespace femsimp::cli {

struct SimplifyArgs {
  std::string input, output;
  SimplifyOptions options;
  bool threads_given = false;     // remote mode: unset threads means "server default"
  std::string stats_json;         // empty: no JSON file
  std::string server;             // empty: run locally
  double deadline_seconds = 0.0;  // remote only; 0 = no deadline
  std::string label;              // remote only; shown in the server's job list and logs
  int max_attempts = 5;           // remote only; calls per job, retries included (retry.h)
  SecurityFlags security;         // remote only: TLS and the bearer token
  bool quiet = false;             // no per-pass rows
  bool drop_face_data = false;    // write OUT without the face groups/fields its format lacks
  bool repair_details = false;    // every repair record in the summary (else the first few)
  bool fe_check = false;          // run the FE check on IN and OUT after the simplification
  fecheck::FeCheckOptions fe_check_options;
};

struct Command {
  enum Kind { kHelp, kSimplify, kCheck } kind = kHelp;
  std::string help_text;  // kHelp: what to print on stdout
  SimplifyArgs simplify;
  CheckArgs check;
};

// Top-level and `simplify` usage, including the exit codes. `femsimp options [--markdown]`
// answers kHelp with the option table (engine/option_table.h) as text or as the README's table.
std::string MainUsage();
std::string SimplifyUsage();

// Parses argv (argv[0] is the program). Errors are usage errors: the message names the flag
// and what is wrong with it; the caller prints it and exits with kExitUsage.
absl::StatusOr<Command> ParseCommandLine(const std::vector<std::string>& args);

// Parses the `simplify` arguments alone (after the subcommand word).
absl::StatusOr<SimplifyArgs> ParseSimplifyArgs(const std::vector<std::string>& args);

// Stores a HOST:PORT value (refuses one without a port separator), e.g. for --server.
flags::FlagSet::Setter ServerAddressSetter(std::string flag, std::string* dst);

}  // namespace femsimp::cli
