// The engine's options, each defined once: name, flag, type, default, range, unit and help.
// SimplifyOptions (simplify.h) stays the typed view the kernel reads; everything else that
// names an option comes from this table or is checked against it: ValidateOptions, the CLI's
// flags and --help (option_flags.h), the proto mapping (proto/wire.cc, by field name), the
// options object of --stats-json, the README's option table (`femsimp options --markdown`) and
// the proto's documented ranges and defaults (tests/service/option_table_test.cc).
#pragma once

#include <string>
#include <variant>
#include <vector>
#include "absl/strings/string_view.h"

#include "absl/status/status.h"
#include "common/range.h"
#include "engine/simplify.h"

namespace femsimp {

enum class OptionType {
  kReal,      // double
  kFraction,  // double; the CLI also takes a percentage ("0.5%")
  kInt,       // int
  kCount,     // uint64_t
  kBool,
  kEnum,  // one of `choices`; the value is the choice's index (the engine enum's value)
};

struct OptionChoice {
  const char* name;      // proto (upper-cased, after the enum's prefix) and JSON
  const char* cli_name;  // on the command line; `name` is accepted too
};

// Where the value lives in SimplifyOptions (or its CellOptions, or its RepairOptions).
using OptionField =
    std::variant<double SimplifyOptions::*, int SimplifyOptions::*, uint64_t SimplifyOptions::*,
                 bool SimplifyOptions::*, CostKind SimplifyOptions::*, Backend SimplifyOptions::*,
                 Preset SimplifyOptions::*, Schedule SimplifyOptions::*,
                 Placement SimplifyOptions::*, DeviationCheck SimplifyOptions::*,
                 int CellOptions::*, bool CellOptions::*, RepairMode RepairOptions::*,
                 double RepairOptions::*, bool RepairOptions::*, HoleFill RepairOptions::*>;

struct OptionSpec {
  const char* name = "";       // snake_case; the proto field name (inside message `group` when set)
  const char* group = "";      // "" or "cell": EngineOptions.cell / SimplifyOptions::cell
  const char* flag = nullptr;  // "--min-angle"; nullptr: not on the command line
  const char* metavar = "";    // "D"; enums and bools: none (enums show their CLI names)
  const char* section = "";    // where --help lists it: "target", "engine", "fidelity", "backend",
                               // "repair"
  OptionType type = OptionType::kReal;
  double default_value = 0;     // SimplifyOptions'; enums: the choice's index; bools: 0 or 1
  Range range = {};             // numbers only
  const char* unit = "";        // "degrees", "KiB", ... or ""
  const char* zero_means = "";  // non-empty: 0 is allowed besides the range and means this
  // Non-empty: the default shown, where callers other than the engine choose it (threads).
  const char* default_note = "";
  const char* help = "";
  std::vector<OptionChoice> choices = {};
  OptionField field = {};

  std::string path() const;  // "min_angle_deg", "cell.spes"
  bool numeric() const { return type != OptionType::kBool && type != OptionType::kEnum; }
  bool cell_only() const { return group[0] != '\0'; }
};

// Every option, in the order of EngineOptions' fields (and of the --stats-json object).
const std::vector<OptionSpec>& OptionTable();
// By path ("cell.spes") or by flag ("--spes"); nullptr when there is none.
const OptionSpec* FindOption(absl::string_view path_or_flag);

double GetOption(const OptionSpec& spec, const SimplifyOptions& o);
void SetOption(const OptionSpec& spec, double value, SimplifyOptions* o);

// "10", "0.9", "true", "gaussian_curvature" (the choice's name).
std::string FormatOptionValue(const OptionSpec& spec, double value);
// The default as the CLI and README show it: "gaussian", "0", "the host's cores; ...".
std::string DefaultText(const OptionSpec& spec);
// "in [0, 60) degrees", "in [0, 1] of the bounding-box diagonal (0: off)"; "" for enums, bools.
std::string RangeText(const OptionSpec& spec);
// Ok, or "NAME = VALUE is out of range: must be <RangeText>" with `name` as given (the option's
// name, or the flag it came from).
absl::Status CheckOptionValue(const OptionSpec& spec, double value, absl::string_view name);

// The README's option table (markdown), generated: `femsimp options --markdown`.
std::string OptionsMarkdown();

}  // namespace femsimp
