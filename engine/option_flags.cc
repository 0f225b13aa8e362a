#include "engine/option_flags.h"

#include "absl/strings/str_cat.h"
#include "engine/option_table.h"

namespace femsimp {
namespace {

flags::NumberKind KindOf(OptionType t) {
  switch (t) {
    case OptionType::kFraction:
      return flags::NumberKind::kFraction;
    case OptionType::kInt:
    case OptionType::kCount:
      return flags::NumberKind::kInteger;
    default:
      return flags::NumberKind::kReal;
  }
}

void AddFlag(flags::FlagSet& set, const OptionSpec& spec, SimplifyOptions* options,
             std::string default_text) {
  auto store = [&spec, options](double v) { SetOption(spec, v, options); };
  if (default_text.empty()) default_text = DefaultText(spec);
  if (spec.type == OptionType::kBool) {
    // A switch turns the option on; the table has no flag for an option that is on by default.
    set.Switch(spec.flag, spec.help, [store] { store(1); });
  } else if (spec.type == OptionType::kEnum) {
    std::vector<std::vector<std::string>> choices;
    for (const OptionChoice& c : spec.choices) choices.push_back({c.cli_name, c.name});
    set.Choice(spec.flag, std::move(choices),
               absl::StrCat(spec.help, " (default ", default_text, ")"),
               [store](size_t i) { store(static_cast<double>(i)); });
  } else {
    set.AddNumber({.name = spec.flag,
                   .metavar = spec.metavar,
                   .help = spec.help,
                   .kind = KindOf(spec.type),
                   .range = spec.range,
                   .unit = spec.unit,
                   .zero_means = spec.zero_means,
                   .default_text = default_text},
                  store);
  }
}

}  // namespace

void AddOptionFlags(flags::FlagSet& set, absl::string_view section, SimplifyOptions* options) {
  for (const OptionSpec& spec : OptionTable())
    if (spec.flag != nullptr && spec.section == section) AddFlag(set, spec, options, "");
}

void AddOptionFlag(flags::FlagSet& set, absl::string_view path, SimplifyOptions* options,
                   std::string default_text) {
  const OptionSpec* spec = FindOption(path);
  if (spec != nullptr && spec->flag != nullptr)
    AddFlag(set, *spec, options, std::move(default_text));
}

absl::Status CheckCellFlags(const flags::FlagSet::Parsed& parsed, const SimplifyOptions& options) {
  if (options.backend == Backend::kCell) return absl::OkStatus();
  for (const OptionSpec& spec : OptionTable())
    if (spec.cell_only() && spec.flag != nullptr && parsed.Given(spec.flag))
      return absl::InvalidArgumentError(absl::StrCat(spec.flag, " needs --backend cell"));
  return absl::OkStatus();
}

}  // namespace femsimp
