// The proto against the option table: every option is a field of EngineOptions (or its
// CellOptions) of the matching type, round-trips through ToProto/FromProto, and the range and
// default its comment in femsimp.proto documents are the table's.
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "engine/option_table.h"
#include "gtest/gtest.h"
#include "proto/wire.h"

namespace femsimp {
namespace {

using google::protobuf::FieldDescriptor;

const google::protobuf::Descriptor* MessageOf(const OptionSpec& s) {
  return s.cell_only() ? v1::CellOptions::descriptor() : v1::EngineOptions::descriptor();
}

TEST(ProtoOptions, EveryOptionIsAFieldOfItsType) {
  for (const OptionSpec& s : OptionTable()) {
    const FieldDescriptor* f = MessageOf(s)->FindFieldByName(s.name);
    ASSERT_NE(f, nullptr) << s.path();
    FieldDescriptor::CppType want = FieldDescriptor::CPPTYPE_DOUBLE;
    if (s.type == OptionType::kInt) want = FieldDescriptor::CPPTYPE_INT32;
    if (s.type == OptionType::kCount) want = FieldDescriptor::CPPTYPE_UINT64;
    if (s.type == OptionType::kBool) want = FieldDescriptor::CPPTYPE_BOOL;
    if (s.type == OptionType::kEnum) want = FieldDescriptor::CPPTYPE_ENUM;
    EXPECT_EQ(f->cpp_type(), want) << s.path();
    if (s.type != OptionType::kEnum) continue;
    // Value 0 is UNSPECIFIED; every choice has its value, named after it.
    const std::string unspecified = f->enum_type()->value(0)->name();
    const std::string prefix = unspecified.substr(0, unspecified.size() - 11);
    for (const OptionChoice& c : s.choices)
      EXPECT_NE(f->enum_type()->FindValueByName(absl::AsciiStrToUpper(prefix + c.name)), nullptr)
          << s.path() << " " << c.name;
  }
  // And no engine field the table lacks.
  for (const auto* d : {v1::EngineOptions::descriptor(), v1::CellOptions::descriptor()})
    for (int i = 0; i < d->field_count(); ++i) {
      const std::string name = d->field(i)->name();
      if (name == "cell") continue;
      EXPECT_NE(FindOption(d == v1::CellOptions::descriptor() ? "cell." + name : name), nullptr)
          << name;
    }
}

// A value other than the default that ValidateOptions accepts.
double OtherValue(const OptionSpec& s, const SimplifyOptions& base) {
  if (s.type == OptionType::kBool) return 1 - s.default_value;
  if (s.type == OptionType::kEnum) return s.default_value == 0 ? 1 : 0;
  const Range& r = s.range;
  std::vector<double> candidates = {r.lo, r.hi, (r.lo + r.hi) / 2, r.lo + 1, 2, 0.5};
  for (double v : candidates) {
    if (s.type != OptionType::kReal && s.type != OptionType::kFraction) v = std::floor(v);
    SimplifyOptions o = base;
    SetOption(s, v, &o);
    if (v != s.default_value && std::isfinite(v) && ValidateOptions(o).ok()) return v;
  }
  ADD_FAILURE() << "no other valid value for " << s.path();
  return s.default_value;
}

TEST(ProtoOptions, EveryOptionRoundTrips) {
  for (const OptionSpec& s : OptionTable()) {
    SimplifyOptions o;
    if (s.cell_only()) o.backend = Backend::kCell;
    const double v = OtherValue(s, o);
    SetOption(s, v, &o);
    v1::EngineOptions m;
    wire::ToProto(o, true, &m);
    absl::StatusOr<SimplifyOptions> back = wire::FromProto(m, 1, 1024);
    ASSERT_TRUE(back.ok()) << s.path() << ": " << back.status();
    EXPECT_EQ(GetOption(s, *back), v) << s.path();
  }
}

// A value out of the documented range is refused before the server caps it: threads 1025 is
// INVALID_ARGUMENT, not quietly capped to the server's --threads_per_job (the hostile probe).
TEST(ProtoOptions, OutOfRangeThreadsAreRefusedBeforeTheCap) {
  for (int threads : {-1, 1025, 1 << 30}) {
    v1::EngineOptions m;
    m.set_threads(threads);
    absl::StatusOr<SimplifyOptions> o = wire::FromProto(m, 1, 2);
    EXPECT_EQ(o.status().code(), absl::StatusCode::kInvalidArgument) << threads;
    EXPECT_NE(o.status().message().find("threads"), std::string::npos) << o.status();
  }
  v1::EngineOptions m;
  m.set_threads(1024);
  absl::StatusOr<SimplifyOptions> o = wire::FromProto(m, 1, 2);
  ASSERT_TRUE(o.ok()) << o.status();
  EXPECT_EQ(o->threads, 2);  // in range: capped at the server's limit
}

// The comment of a field in femsimp.proto: its trailing comment with continuation lines, or
// else the comment lines right above it.
std::string CommentOf(const std::vector<std::string>& lines, const std::string& message,
                      const std::string& field) {
  const std::regex decl("^\\s*(optional\\s+)?\\w+\\s+" + field + "\\s*=\\s*\\d+;(.*)$");
  bool inside = false;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].rfind("message ", 0) == 0) inside = lines[i] == "message " + message + " {";
    std::smatch m;
    if (!inside || !std::regex_match(lines[i], m, decl)) continue;
    std::string trailing = m[2];
    const size_t column = lines[i].find("//");
    for (size_t j = i + 1;
         j < lines.size() && column != std::string::npos && lines[j].find("//") == column &&
         absl::StripAsciiWhitespace(lines[j]).rfind("//", 0) == 0;
         ++j)
      absl::StrAppend(&trailing, " ", lines[j]);
    if (trailing.find("//") != std::string::npos) return trailing;
    std::string above;
    for (size_t j = i; j-- > 0 && absl::StripAsciiWhitespace(lines[j]).rfind("//", 0) == 0;)
      above = absl::StrCat(lines[j], " ", above);
    return above;
  }
  return "";
}

TEST(ProtoOptions, DocumentedRangesAndDefaultsAreTheTables) {
  std::ifstream f(std::string(FEMSIMP_SOURCE_DIR) + "/proto/femsimp/v1/femsimp.proto");
  ASSERT_TRUE(f);
  std::stringstream text;
  text << f.rdbuf();
  const std::vector<std::string> lines = absl::StrSplit(text.str(), '\n');
  const std::regex range("([\\[(]-?[0-9.e+]+, -?[0-9.e+]+[\\])])|([<>]=? -?[0-9.e+]+)");
  const std::regex dflt("default ([^\\s;,()]+)");
  for (const OptionSpec& s : OptionTable()) {
    const std::string comment =
        CommentOf(lines, s.cell_only() ? "CellOptions" : "EngineOptions", s.name);
    ASSERT_NE(comment, "") << s.path() << " has no comment in femsimp.proto";
    std::smatch m;
    if (s.numeric()) {
      const std::string text = s.range.Text();
      const std::string want = text.rfind("in ", 0) == 0 ? text.substr(3) : text;
      ASSERT_TRUE(std::regex_search(comment, m, range)) << s.path() << ": no range in " << comment;
      EXPECT_EQ(m.str(0), want) << s.path() << ": femsimp.proto documents another range";
    }
    if (s.default_note[0] != '\0') continue;  // chosen by the server (threads)
    ASSERT_TRUE(std::regex_search(comment, m, dflt)) << s.path() << ": no default in " << comment;
    std::string documented = m.str(1);
    if (!documented.empty() && documented.back() == '.') documented.pop_back();
    EXPECT_EQ(documented, FormatOptionValue(s, s.default_value))
        << s.path() << ": femsimp.proto documents another default";
  }
}

}  // namespace
}  // namespace femsimp
