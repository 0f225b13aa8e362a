// The option table: one entry per option, defaults in range, ValidateOptions speaking the
// table's words, and the README's table generated from it.
#include "engine/option_table.h"

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "gtest/gtest.h"

namespace femsimp {
namespace {

// A value just outside the option's range (0 excepted where 0 is allowed).
double OutsideOf(const Range& r) { return r.hi != Range::kInf ? r.hi + 1 : r.lo - 1; }

TEST(OptionTable, NamesFlagsAndDefaultsAreConsistent) {
  std::set<std::string> paths, flags;
  for (const OptionSpec& s : OptionTable()) {
    EXPECT_TRUE(paths.insert(s.path()).second) << s.path();
    if (s.flag != nullptr) {
      EXPECT_TRUE(flags.insert(s.flag).second) << s.flag;
      EXPECT_EQ(std::string(s.flag).rfind("--", 0), 0u) << s.flag;
      EXPECT_EQ(FindOption(s.flag), &s);
    }
    EXPECT_EQ(FindOption(s.path()), &s);
    EXPECT_TRUE(CheckOptionValue(s, s.default_value, s.name).ok()) << s.path();
    EXPECT_NE(std::string(s.help), "") << s.path();
    EXPECT_EQ(s.type == OptionType::kEnum, !s.choices.empty()) << s.path();
  }
  EXPECT_TRUE(ValidateOptions(SimplifyOptions()).ok());
  SimplifyOptions cell;
  cell.backend = Backend::kCell;
  EXPECT_TRUE(ValidateOptions(cell).ok());
  EXPECT_EQ(FindOption("cell.ls_cache_kib")->default_value, CellOptions().ls_cache_kib);
}

TEST(OptionTable, GetAndSetReachEveryField) {
  for (const OptionSpec& s : OptionTable()) {
    SimplifyOptions o;
    const double v = s.type == OptionType::kBool   ? 1 - s.default_value
                     : s.type == OptionType::kEnum ? static_cast<double>(s.choices.size() - 1)
                                                   : s.default_value + 1;
    SetOption(s, v, &o);
    EXPECT_EQ(GetOption(s, o), v) << s.path();
    for (const OptionSpec& other : OptionTable()) {
      if (&other == &s) continue;
      EXPECT_EQ(GetOption(other, o), other.default_value) << other.path();
    }
  }
}

TEST(OptionTable, ValidateOptionsSpeaksTheTablesWords) {
  SimplifyOptions o;
  o.min_angle_deg = 75;
  EXPECT_EQ(ValidateOptions(o).message(),
            "min_angle_deg = 75 is out of range: must be in [0, 60) degrees");
  for (const OptionSpec& s : OptionTable()) {
    if (!s.numeric()) continue;
    SimplifyOptions bad;
    bad.backend = Backend::kCell;
    const double v = OutsideOf(s.range);
    SetOption(s, v, &bad);
    EXPECT_EQ(ValidateOptions(bad).message(), std::string(s.name) + " = " +
                                                  FormatOptionValue(s, v) +
                                                  " is out of range: must be " + RangeText(s))
        << s.path();
  }
  // The cell options are checked (and read) only for the cell back end.
  SimplifyOptions native;
  native.cell.spes = 0;
  EXPECT_TRUE(ValidateOptions(native).ok());
}

TEST(OptionTable, RulesBetweenOptions) {
  SimplifyOptions both;
  both.ratio = 0.5;
  both.target_vertices = 10;
  EXPECT_EQ(ValidateOptions(both).message(), "give either ratio or target_vertices, not both");
  SimplifyOptions cell;
  cell.backend = Backend::kCell;
  cell.cell.ls_cache_kib = 200;
  EXPECT_NE(ValidateOptions(cell).message().find("ls_cache_kib = 200 is out of range: must be a "
                                                 "power of two"),
            std::string::npos);
  cell.cell.ls_cache_kib = 256;
  EXPECT_EQ(ValidateOptions(cell).message(),
            "ls_cache_kib = 256 is out of range: must be below local_store_kib = 256");
}

TEST(OptionTable, ReadmeHoldsTheGeneratedTable) {
  std::ifstream f(std::string(FEMSIMP_SOURCE_DIR) + "/README.md");
  ASSERT_TRUE(f) << "README.md not found";
  std::stringstream readme;
  readme << f.rdbuf();
  EXPECT_NE(readme.str().find(OptionsMarkdown()), std::string::npos)
      << "README.md's option table is not `femsimp options --markdown`:\n"
      << OptionsMarkdown();
}

}  // namespace
}  // namespace femsimp
