#include "bench/mesh_args.h"

#include <cstdio>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace femsimp::bench {

std::optional<int> ParseMeshAndNumbers(int argc, char** argv, const char* program,
                                       std::vector<PositionalNumber>& numbers, std::string* mesh) {
  std::string usage = absl::StrCat("Usage: ", program, " MESH");
  for (const PositionalNumber& n : numbers)
    absl::StrAppendFormat(&usage, " [%s=%g]", n.name, n.value);
  absl::StrAppend(&usage, "\n\n");
  flags::FlagSet flags(program);
  flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit = flags.ParseMain(argc, argv, usage, "", &parsed)) return exit;
  const std::vector<std::string>& args = parsed.positional;
  if (args.empty() || args.size() > numbers.size() + 1) {
    std::fprintf(stderr, "%s: needs MESH and at most %zu numbers (see --help)\n", program,
                 numbers.size());
    return flags::kUsageExit;
  }
  for (size_t i = 1; i < args.size(); ++i) {
    PositionalNumber& n = numbers[i - 1];
    absl::StatusOr<double> v = flags::ParseNumberIn(n.name, args[i], n.kind, n.range);
    if (!v.ok()) {
      std::fprintf(stderr, "%s: %s\n", program, std::string(v.status().message()).c_str());
      return flags::kUsageExit;
    }
    n.value = *v;
  }
  *mesh = args[0];
  return std::nullopt;
}

}  // namespace femsimp::bench
