#include "common/flags.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"

namespace femsimp::flags {

std::string RangeWords(const Range& range, absl::string_view unit, absl::string_view zero_means) {
  std::string s = range.Text();
  if (!unit.empty()) absl::StrAppend(&s, " ", unit);
  if (!zero_means.empty()) absl::StrAppend(&s, " (0: ", zero_means, ")");
  return s;
}

absl::Status OutOfRange(absl::string_view name, absl::string_view value, const Range& range,
                        absl::string_view unit, absl::string_view zero_means) {
  return absl::InvalidArgumentError(absl::StrCat(name, " = ", value, " is out of range: must be ",
                                                 RangeWords(range, unit, zero_means)));
}

absl::StatusOr<double> ParseNumber(absl::string_view flag, absl::string_view value,
                                   NumberKind kind) {
  if (kind == NumberKind::kInteger) {
    int64_t i;
    if (!absl::SimpleAtoi(value, &i))
      return absl::InvalidArgumentError(absl::StrCat(flag, ": '", value, "' is not an integer"));
    return static_cast<double>(i);
  }
  absl::string_view number = value;
  const bool percent = kind == NumberKind::kFraction && absl::ConsumeSuffix(&number, "%");
  double d;
  if (!absl::SimpleAtod(number, &d) || !std::isfinite(d))
    return absl::InvalidArgumentError(absl::StrCat(flag, ": '", value, "' is not a finite number",
                                                   percent ? " or percentage" : ""));
  return percent ? d / 100.0 : d;
}

absl::StatusOr<double> ParseNumberIn(absl::string_view flag, absl::string_view value,
                                     NumberKind kind, const Range& range, absl::string_view unit,
                                     absl::string_view zero_means) {
  absl::StatusOr<double> v = ParseNumber(flag, value, kind);
  if (!v.ok()) return v;
  if (!range.Contains(*v) && !(*v == 0 && !zero_means.empty()))
    return OutOfRange(flag, FormatNumber(*v), range, unit, zero_means);
  return v;
}

std::string HelpEntry(absl::string_view flag_and_metavar, absl::string_view text) {
  std::vector<std::string> lines;
  for (absl::string_view word : absl::StrSplit(text, ' ', absl::SkipEmpty())) {
    if (lines.empty() || kHelpColumn + lines.back().size() + 1 + word.size() > kHelpWidth)
      lines.emplace_back();
    absl::StrAppend(&lines.back(), lines.back().empty() ? "" : " ", word);
  }
  std::string head = absl::StrCat("  ", flag_and_metavar);
  std::string out;
  if (head.size() + 2 > kHelpColumn || lines.empty()) {
    out = head + "\n";
    head.clear();
  }
  for (const std::string& line : lines) {
    absl::StrAppend(&out, head, std::string(kHelpColumn - head.size(), ' '), line, "\n");
    head.clear();
  }
  return out;
}

void FlagSet::Section(std::string heading) { lines_.push_back({std::move(heading), 0}); }

void FlagSet::Value(std::string name, std::string metavar, std::string help, Setter set) {
  lines_.push_back({"", flags_.size()});
  flags_.push_back({std::move(name), std::move(metavar), std::move(help), std::move(set), {}});
}

void FlagSet::Switch(std::string name, std::string help, bool* dst) {
  Switch(std::move(name), std::move(help), [dst] { *dst = true; });
}

void FlagSet::Switch(std::string name, std::string help, std::function<void()> on) {
  lines_.push_back({"", flags_.size()});
  flags_.push_back({std::move(name), "", std::move(help), nullptr, std::move(on)});
}

void FlagSet::String(std::string name, std::string metavar, std::string help, std::string* dst) {
  Value(std::move(name), std::move(metavar), std::move(help), [dst](const std::string& v) {
    *dst = v;
    return absl::OkStatus();
  });
}

void FlagSet::AddNumber(NumberFlag f, std::function<void(double)> store) {
  std::string help = f.help;
  if (f.range.bounded() || !f.zero_means.empty())
    absl::StrAppend(&help, ", ", RangeWords(f.range, f.unit, f.zero_means));
  if (!f.default_text.empty()) absl::StrAppend(&help, " (default ", f.default_text, ")");
  help += f.more;
  Value(f.name, f.metavar, std::move(help), [f, store](const std::string& value) -> absl::Status {
    absl::StatusOr<double> v = ParseNumberIn(f.name, value, f.kind, f.range, f.unit, f.zero_means);
    if (!v.ok()) return v.status();
    store(*v);
    return absl::OkStatus();
  });
}

void FlagSet::Choice(std::string name, std::vector<std::vector<std::string>> choices,
                     std::string help, std::function<void(size_t index)> store) {
  std::vector<std::string> shown;
  for (const auto& spellings : choices) shown.push_back(spellings.front());
  Value(name, absl::StrJoin(shown, "|"), std::move(help),
        [name, choices, shown, store](const std::string& value) -> absl::Status {
          for (size_t i = 0; i < choices.size(); ++i)
            for (const std::string& spelling : choices[i])
              if (value == spelling) {
                store(i);
                return absl::OkStatus();
              }
          return absl::InvalidArgumentError(
              absl::StrCat(name, ": '", value, "' is not one of ", absl::StrJoin(shown, ", ")));
        });
}

void FlagSet::AllowFlagfile() { flagfile_ = true; }

const FlagSet::Flag* FlagSet::Find(absl::string_view name) const {
  for (const Flag& f : flags_)
    if (f.name == name) return &f;
  return nullptr;
}

absl::Status FlagSet::Expand(const std::vector<std::string>& args, std::vector<std::string>* out,
                             int depth) const {
  for (size_t i = 0; i < args.size(); ++i) {
    absl::string_view a = args[i];
    if (!flagfile_ || a == "--") {
      out->insert(out->end(), args.begin() + i, args.end());
      return absl::OkStatus();
    }
    std::string path;
    if (absl::ConsumePrefix(&a, "--flagfile=")) {
      path = std::string(a);
    } else if (a == "--flagfile") {
      if (i + 1 >= args.size()) return absl::InvalidArgumentError("--flagfile needs a value");
      path = args[++i];
    } else {
      out->push_back(args[i]);
      continue;
    }
    if (depth >= 8)
      return absl::InvalidArgumentError(absl::StrCat("--flagfile: '", path, "' nests too deep"));
    std::ifstream file(path);
    if (!file)
      return absl::InvalidArgumentError(absl::StrCat("--flagfile: cannot read '", path, "'"));
    std::vector<std::string> lines;
    for (std::string line; std::getline(file, line);) {
      absl::string_view l = absl::StripAsciiWhitespace(line);
      if (!l.empty() && l[0] != '#') lines.emplace_back(l);
    }
    if (absl::Status s = Expand(lines, out, depth + 1); !s.ok()) return s;
  }
  return absl::OkStatus();
}

absl::StatusOr<FlagSet::Parsed> FlagSet::Parse(const std::vector<std::string>& raw) const {
  Parsed parsed;
  for (const std::string& a : raw) {
    if (a == "--") break;
    // --helpfull: Abseil's name for it (every flag is always listed here).
    if (a == "--help" || a == "--helpfull" || a == "-h") {
      parsed.help = true;
      return parsed;
    }
  }
  std::vector<std::string> args;
  if (absl::Status s = Expand(raw, &args, 0); !s.ok()) return s;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--") {
      parsed.positional.insert(parsed.positional.end(), args.begin() + i + 1, args.end());
      break;
    }
    if (a.size() < 2 || a[0] != '-') {
      parsed.positional.push_back(a);
      continue;
    }
    const size_t eq = a.find('=');
    const std::string name = a.substr(0, eq);
    const Flag* flag = absl::StartsWith(name, "--") ? Find(name) : nullptr;
    if (flag == nullptr)
      return absl::InvalidArgumentError(
          absl::StrCat("unknown option '", name, "' (see ", program_, " --help)"));
    if (!flag->set) {
      if (eq != std::string::npos)
        return absl::InvalidArgumentError(absl::StrCat(name, " takes no value"));
      flag->on();
    } else {
      std::string value;
      if (eq != std::string::npos) {
        value = a.substr(eq + 1);
      } else if (i + 1 < args.size()) {
        value = args[++i];
      } else {
        return absl::InvalidArgumentError(absl::StrCat(name, " needs a value"));
      }
      if (absl::Status s = flag->set(value); !s.ok()) return s;
    }
    parsed.given.insert(name);
  }
  return parsed;
}

std::string FlagSet::Help() const {
  std::string out;
  for (const Line& line : lines_) {
    if (!line.heading.empty()) {
      absl::StrAppend(&out, line.heading, "\n");
      continue;
    }
    const Flag& f = flags_[line.flag];
    absl::StrAppend(
        &out, HelpEntry(f.metavar.empty() ? f.name : absl::StrCat(f.name, " ", f.metavar), f.help));
  }
  if (flagfile_)
    absl::StrAppend(&out, HelpEntry("--flagfile FILE",
                                    "read more flags from FILE, one a line (`#` lines skipped)"));
  absl::StrAppend(&out, HelpEntry("--help", "this text (also --helpfull)"));
  return out;
}

std::optional<int> FlagSet::ParseMain(int argc, char** argv, absl::string_view head,
                                      absl::string_view tail, Parsed* parsed) const {
  absl::StatusOr<Parsed> p = Parse(std::vector<std::string>(argv + 1, argv + argc));
  if (!p.ok()) {
    std::fprintf(stderr, "%s: %s\n", program_.c_str(), std::string(p.status().message()).c_str());
    return kUsageExit;
  }
  if (p->help) {
    std::fputs(absl::StrCat(head, Help(), tail).c_str(), stdout);
    return 0;
  }
  *parsed = std::move(*p);
  return std::nullopt;
}

std::vector<std::string> SplitList(absl::string_view value) {
  return absl::StrSplit(value, ',', absl::SkipEmpty());
}

}  // namespace femsimp::flags
