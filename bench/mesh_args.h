// The command line of the cost benchmarks: MESH, then positional numbers, each with a default
// and a range (the option table's where the number is an engine option), e.g.
// `schedule_cost MESH [REPEATS=3] [THREADS=2]`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/flags.h"
#include "common/range.h"

namespace femsimp::bench {

struct PositionalNumber {
  const char* name;
  double value;  // the default; replaced where given
  flags::NumberKind kind;
  Range range;
};

// Parses MESH [NUMBER ...] into `mesh` and `numbers`. Where the run should end (--help, a usage
// error, said on stderr), the exit code.
std::optional<int> ParseMeshAndNumbers(int argc, char** argv, const char* program,
                                       std::vector<PositionalNumber>& numbers, std::string* mesh);

}  // namespace femsimp::bench
