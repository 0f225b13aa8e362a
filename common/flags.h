// One argument parser for every executable (femsimp, femsimp-load, femsimp-server, bench/):
// `--flag VALUE` and `--flag=VALUE`, switches without a value, positional arguments, `--` to end
// the flags, `--help`/`-h`, optionally `--flagfile=FILE` (one argument a line, `#` comments),
// and one layout for the help text. Unknown flags, missing or malformed values and values out
// of range are usage errors whose message names the flag and what is wrong, in the words of
// the option table (common/range.h): "--min-angle = 75 is out of range: must be in [0, 60)
// degrees". No gRPC and no engine in here.
#pragma once

#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>
#include "absl/strings/string_view.h"

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/range.h"

namespace femsimp::flags {

// Exit code of a usage error, in every executable.
inline constexpr int kUsageExit = 2;

// Help layout: flag and metavar from column 2, the text from column kHelpColumn, wrapped at
// kHelpWidth.
inline constexpr size_t kHelpColumn = 28;
inline constexpr size_t kHelpWidth = 100;

// How a number is written on the command line.
enum class NumberKind {
  kReal,      // a finite number
  kFraction,  // a finite number, or a percentage of one ("0.5%" = 0.005)
  kInteger,   // a whole number
};

// "in [0, 60) degrees (0: off)": the range, its unit and what 0 means when 0 is allowed.
std::string RangeWords(const Range& range, absl::string_view unit = "",
                       absl::string_view zero_means = "");
// "NAME = VALUE is out of range: must be <RangeWords>".
absl::Status OutOfRange(absl::string_view name, absl::string_view value, const Range& range,
                        absl::string_view unit = "", absl::string_view zero_means = "");

// Strict parsing: the whole value must be a number of the kind; the message names the flag.
absl::StatusOr<double> ParseNumber(absl::string_view flag, absl::string_view value,
                                   NumberKind kind);
// Parsed and inside the range (or 0 when zero_means is given).
absl::StatusOr<double> ParseNumberIn(absl::string_view flag, absl::string_view value,
                                     NumberKind kind, const Range& range,
                                     absl::string_view unit = "",
                                     absl::string_view zero_means = "");

// One help entry: "  --flag METAVAR" and the text, wrapped.
std::string HelpEntry(absl::string_view flag_and_metavar, absl::string_view text);

// A numeric flag's description: its help line is "<help>, <range words> (default <dflt>)<more>".
struct NumberFlag {
  std::string name = "";     // "--clients"
  std::string metavar = "";  // "C"
  std::string help = "";
  NumberKind kind = NumberKind::kReal;
  Range range = {};
  std::string unit = "";          // "seconds", "degrees", ...
  std::string zero_means = "";    // non-empty: 0 is allowed besides the range, meaning this
  std::string default_text = "";  // empty: no default shown
  std::string more = "";          // appended after the default, e.g. ": ..."
};

class FlagSet {
 public:
  using Setter = std::function<absl::Status(const std::string& value)>;

  // program: how usage errors refer to the help, e.g. "femsimp simplify".
  explicit FlagSet(std::string program) : program_(std::move(program)) {}

  // Help layout: a heading line ("Engine:") before the flags added next.
  void Section(std::string heading);
  // A flag that takes a value; set parses and stores it, or says what is wrong.
  void Value(std::string name, std::string metavar, std::string help, Setter set);
  // A switch: no value; sets *dst to true, or calls on.
  void Switch(std::string name, std::string help, bool* dst);
  void Switch(std::string name, std::string help, std::function<void()> on);
  void String(std::string name, std::string metavar, std::string help, std::string* dst);
  // A number checked against its range; stores into an int, long long, uint64_t or double.
  template <typename T>
  void Number(NumberFlag flag, T* dst) {
    AddNumber(std::move(flag), [dst](double v) { *dst = static_cast<T>(v); });
  }
  void AddNumber(NumberFlag flag, std::function<void(double)> store);
  // One of several words, e.g. --backend native|cell. Each choice is a list of spellings: the
  // first is shown in the help and in messages, the others are accepted too.
  void Choice(std::string name, std::vector<std::vector<std::string>> choices, std::string help,
              std::function<void(size_t index)> store);
  // --flagfile=FILE is read in place: one argument a line, blank lines and `#` lines skipped.
  void AllowFlagfile();

  struct Parsed {
    std::vector<std::string> positional;
    bool help = false;  // --help or -h was given (nothing else was checked)
    std::set<std::string> given;
    bool Given(const std::string& name) const { return given.count(name) > 0; }
  };
  // args: without the program (and subcommand). A repeated flag: the last value wins.
  absl::StatusOr<Parsed> Parse(const std::vector<std::string>& args) const;

  // Every flag, in the order added, under its section headings; --help last.
  std::string Help() const;

  // For a main(): parses argv[1..] into *parsed. On --help prints head + Help() + tail to stdout
  // and returns 0; on a usage error prints "PROGRAM: message" to stderr and returns kUsageExit;
  // otherwise returns nullopt (go on).
  std::optional<int> ParseMain(int argc, char** argv, absl::string_view head,
                               absl::string_view tail, Parsed* parsed) const;

 private:
  struct Flag {
    std::string name, metavar, help;
    Setter set;                // null: a switch
    std::function<void()> on;  // a switch
  };
  struct Line {  // a section heading, or a flag
    std::string heading;
    size_t flag = 0;
  };
  absl::Status Expand(const std::vector<std::string>& args, std::vector<std::string>* out,
                      int depth) const;
  const Flag* Find(absl::string_view name) const;

  std::string program_;
  std::vector<Flag> flags_;
  std::vector<Line> lines_;
  bool flagfile_ = false;
};

// Splits "a,b,c" into its non-empty parts (list-valued flags such as --threads=1,2).
std::vector<std::string> SplitList(absl::string_view value);

}  // namespace femsimp::flags
