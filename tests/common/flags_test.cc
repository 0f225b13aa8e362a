// The one argument parser: value forms, switches, positionals, errors in the table's words,
// --flagfile, and the help layout.
#include "common/flags.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "absl/strings/str_split.h"
#include "gtest/gtest.h"

namespace femsimp::flags {
namespace {

struct Target {
  double angle = 10;
  int count = 1;
  double share = 0.5;
  bool quiet = false;
  std::string name;
};

FlagSet Make(Target* t) {
  FlagSet set("prog");
  set.Section("Numbers:");
  set.Number({.name = "--angle",
              .metavar = "D",
              .help = "an angle",
              .range = Range::ClosedOpen(0, 60),
              .unit = "degrees",
              .default_text = "10"},
             &t->angle);
  set.Number({.name = "--count",
              .metavar = "N",
              .help = "a count",
              .kind = NumberKind::kInteger,
              .range = Range::Closed(1, 100)},
             &t->count);
  set.Number({.name = "--share",
              .metavar = "F",
              .help = "a share",
              .kind = NumberKind::kFraction,
              .range = Range::Closed(0, 1),
              .zero_means = "off"},
             &t->share);
  set.Section("Other:");
  set.Switch("--quiet", "say less", &t->quiet);
  set.String("--name", "TEXT", "a name", &t->name);
  return set;
}

TEST(Flags, ValueFormsSwitchesAndPositionals) {
  Target t;
  auto p = Make(&t).Parse({"a", "--angle", "12.5", "--count=7", "--share", "2%", "--quiet", "b",
                           "--name=x=y", "--", "--angle"});
  ASSERT_TRUE(p.ok()) << p.status();
  EXPECT_EQ(t.angle, 12.5);
  EXPECT_EQ(t.count, 7);
  EXPECT_DOUBLE_EQ(t.share, 0.02);
  EXPECT_TRUE(t.quiet);
  EXPECT_EQ(t.name, "x=y");
  EXPECT_EQ(p->positional, (std::vector<std::string>{"a", "b", "--angle"}));
  EXPECT_TRUE(p->Given("--count"));
  EXPECT_FALSE(p->Given("--name2"));
  EXPECT_FALSE(p->help);
}

TEST(Flags, ErrorsNameTheFlagInTheRangesWords) {
  struct Case {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"--angle", "75"}, "--angle = 75 is out of range: must be in [0, 60) degrees"},
      {{"--angle=nan"}, "--angle: 'nan' is not a finite number"},
      {{"--count", "1.5"}, "--count: '1.5' is not an integer"},
      {{"--count", "0"}, "--count = 0 is out of range: must be in [1, 100]"},
      {{"--share", "x%"}, "--share: 'x%' is not a finite number or percentage"},
      {{"--share", "150%"}, "--share = 1.5 is out of range: must be in [0, 1] (0: off)"},
      {{"--quiet=1"}, "--quiet takes no value"},
      {{"--count"}, "--count needs a value"},
      {{"--bogus"}, "unknown option '--bogus' (see prog --help)"},
      {{"-x"}, "unknown option '-x' (see prog --help)"},
  };
  for (const Case& c : cases) {
    Target t;
    auto p = Make(&t).Parse(c.args);
    ASSERT_FALSE(p.ok()) << c.message;
    EXPECT_EQ(p.status().message(), c.message);
  }
}

TEST(Flags, HelpWinsAndHasOneLayout) {
  Target t;
  FlagSet set = Make(&t);
  auto p = set.Parse({"--bogus", "-h"});
  ASSERT_TRUE(p.ok());
  EXPECT_TRUE(p->help);
  const std::string help = set.Help();
  EXPECT_NE(help.find("Numbers:\n  --angle D                 an angle, in [0, 60) degrees "
                      "(default 10)\n"),
            std::string::npos)
      << help;
  EXPECT_NE(help.find("  --share F                 a share, in [0, 1] (0: off)\n"),
            std::string::npos);
  EXPECT_NE(help.find("  --help                    this text (also --helpfull)\n"),
            std::string::npos);
  auto full = set.Parse({"--helpfull"});
  ASSERT_TRUE(full.ok());
  EXPECT_TRUE(full->help);
  for (absl::string_view line : absl::StrSplit(help, '\n')) EXPECT_LE(line.size(), kHelpWidth);
  const std::string long_entry = HelpEntry("--a-very-long-flag-name VALUE", std::string(30, 'w'));
  EXPECT_EQ(long_entry, "  --a-very-long-flag-name VALUE\n" + std::string(kHelpColumn, ' ') +
                            std::string(30, 'w') + "\n");
}

TEST(Flags, FlagfileIsReadInPlace) {
  const std::string path = ::testing::TempDir() + "/flags_test.flags";
  {
    std::ofstream f(path);
    f << "# comment\n--count=5\n\n  --name=from-file  \n";
  }
  Target t;
  FlagSet set = Make(&t);
  set.AllowFlagfile();
  auto p = set.Parse({"--flagfile=" + path, "--name", "later"});
  ASSERT_TRUE(p.ok()) << p.status();
  EXPECT_EQ(t.count, 5);
  EXPECT_EQ(t.name, "later");
  auto missing = set.Parse({"--flagfile", path + ".none"});
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("cannot read"), std::string::npos);
  Target u;
  EXPECT_FALSE(Make(&u).Parse({"--flagfile=" + path}).ok());  // not allowed there
  std::remove(path.c_str());
}

TEST(Range, Words) {
  EXPECT_EQ(Range::ClosedOpen(0, 60).Text(), "in [0, 60)");
  EXPECT_EQ(Range::OpenClosed(0, 180).Text(), "in (0, 180]");
  EXPECT_EQ(Range::AtLeast(1).Text(), ">= 1");
  EXPECT_EQ(Range::Above(0).Text(), "> 0");
  EXPECT_EQ(Range::Closed(1, 4e9).Text(), "in [1, 4000000000]");
  EXPECT_FALSE(Range::AtLeast(0).Contains(Range::kInf));
  EXPECT_FALSE(Range::AtLeast(0).Contains(std::nan("")));
  EXPECT_EQ(RangeWords(Range::Closed(0, 1), "of the diagonal", "off"),
            "in [0, 1] of the diagonal (0: off)");
}

}  // namespace
}  // namespace femsimp::flags
