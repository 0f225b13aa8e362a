#include "engine/io/survey.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"

namespace femsimp {
namespace {

absl::Status Bad(auto&&... parts) { return absl::InvalidArgumentError(absl::StrCat(parts...)); }

constexpr absl::string_view kTrianglesOnly = "femsimp accepts triangles only; triangulate first";

// Splits text into lines, counting them from 1; strips a trailing '\r'.
class Lines {
 public:
  explicit Lines(absl::string_view data) : data_(data) {}
  bool Next(absl::string_view* line) {
    if (pos_ >= data_.size()) return false;
    size_t end = data_.find('\n', pos_);
    if (end == absl::string_view::npos) end = data_.size();
    *line = data_.substr(pos_, end - pos_);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  // The next line that is neither blank nor a '#' comment.
  bool NextContent(absl::string_view* line) {
    while (Next(line)) {
      absl::string_view s = absl::StripAsciiWhitespace(*line);
      if (!s.empty() && s[0] != '#') return true;
    }
    return false;
  }
  size_t number() const { return number_; }
  size_t offset() const { return std::min(pos_, data_.size()); }

 private:
  absl::string_view data_;
  size_t pos_ = 0;
  size_t number_ = 0;
};

std::vector<absl::string_view> Tokens(absl::string_view line) {
  return absl::StrSplit(line, absl::ByAnyChar(" \t\r\v\f"), absl::SkipEmpty());
}

// Accepts what a C++ stream accepts, plus "nan"/"inf" so they can be reported as such.
bool ParseDouble(absl::string_view s, double* out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  return ec == std::errc() && p == s.data() + s.size();
}

bool ParseInt(absl::string_view s, int64_t* out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  return ec == std::errc() && p == s.data() + s.size();
}

// Coordinates are stored as float: a double that overflows float is as bad as "inf".
bool FiniteAsFloat(double d) { return std::isfinite(static_cast<float>(d)); }

// Parses the first three tokens as a finite vertex position; `where` names the vertex.
absl::Status CheckPosition(const std::vector<absl::string_view>& tok, size_t first,
                           absl::string_view where) {
  if (tok.size() < first + 3)
    return Bad(where, ": expected 3 coordinates, found ", tok.size() - first);
  for (size_t i = first; i < first + 3; ++i) {
    double d;
    if (!ParseDouble(tok[i], &d)) return Bad(where, ": cannot parse '", tok[i], "' as a number");
    if (!FiniteAsFloat(d)) return Bad(where, ": coordinate '", tok[i], "' is not a finite float");
  }
  return absl::OkStatus();
}

absl::Status Polygon(size_t face, size_t corners, absl::string_view where) {
  return Bad("face ", face, where, " has ", corners, " vertices: ", kTrianglesOnly);
}

// ---------------------------------------------------------------------------------- OFF

absl::StatusOr<MeshFileSurvey> SurveyOff(absl::string_view data) {
  Lines lines(data);
  absl::string_view line;
  if (!lines.NextContent(&line)) return Bad("no OFF header");
  std::vector<absl::string_view> tok = Tokens(line);
  const absl::string_view key = tok[0];
  // OFF with optional ST (texture), C (colour), N (normal) prefixes; 4OFF/nOFF are not 3D.
  if (!absl::EndsWith(key, "OFF") || absl::StrContains(key, "4") || key[0] == 'n')
    return Bad("line ", lines.number(), ": expected an OFF header, found '", key, "'");
  MeshFileSurvey s;
  s.binary = tok.size() > 1 && tok[1] == "BINARY";
  if (s.binary) {
    // Binary OFF: three 32-bit counts, 12 bytes per vertex, at least 16 per triangle.
    const absl::string_view rest = data.substr(lines.offset());
    if (rest.size() < 12) return Bad("binary OFF: file ends inside the counts");
    uint32_t c[2];
    std::memcpy(c, rest.data(), 8);
    if (uint64_t(c[0]) * 12 > rest.size()) {  // OFF's binary form is big-endian by the spec
      c[0] = __builtin_bswap32(c[0]);
      c[1] = __builtin_bswap32(c[1]);
    }
    const uint64_t need = 12 + uint64_t(c[0]) * 12 + uint64_t(c[1]) * 16;
    if (need > rest.size())
      return Bad("binary OFF truncated: header announces ", c[0], " vertices and ", c[1],
                 " faces (at least ", need, " bytes of data) but only ", rest.size(),
                 " bytes follow the header");
    s.vertices = c[0];
    s.faces = c[1];
    return s;
  }
  tok.erase(tok.begin());
  if (tok.empty()) {
    if (!lines.NextContent(&line)) return Bad("OFF header has no vertex and face counts");
    tok = Tokens(line);
  }
  int64_t nv, nf;
  if (tok.size() < 2 || !ParseInt(tok[0], &nv) || !ParseInt(tok[1], &nf) || nv < 0 || nf < 0)
    return Bad("line ", lines.number(), ": expected vertex and face counts, found '", line, "'");
  s.vertices = size_t(nv);
  s.faces = size_t(nf);
  const auto truncated = [&](absl::string_view what, size_t got) {
    return Bad("truncated: header announces ", nv, " vertices and ", nf,
               " faces but the file ends after ", got, " ", what, " (line ", lines.number(), ")");
  };
  for (size_t v = 0; v < s.vertices; ++v) {
    if (!lines.NextContent(&line)) return truncated("vertices", v);
    absl::Status st =
        CheckPosition(Tokens(line), 0, absl::StrCat("vertex ", v, " (line ", lines.number(), ")"));
    if (!st.ok()) return st;
  }
  for (size_t f = 0; f < s.faces; ++f) {
    if (!lines.NextContent(&line)) return truncated("faces", f);
    tok = Tokens(line);
    const std::string where = absl::StrCat(" (line ", lines.number(), ")");
    int64_t n;
    if (!ParseInt(tok[0], &n))
      return Bad("face ", f, where, ": cannot parse '", tok[0], "' as a vertex count");
    if (n != 3) return Polygon(f, size_t(std::max<int64_t>(n, 0)), where);
    if (tok.size() < 4) return Bad("face ", f, where, ": expected 3 vertex indices");
    for (size_t i = 1; i <= 3; ++i) {
      int64_t idx;
      if (!ParseInt(tok[i], &idx))
        return Bad("face ", f, where, ": cannot parse '", tok[i], "' as a vertex index");
      if (idx < 0) return Bad("face ", f, where, " has a negative vertex index ", idx);
    }
  }
  return s;
}

// ---------------------------------------------------------------------------------- OBJ

absl::StatusOr<MeshFileSurvey> SurveyObj(absl::string_view data) {
  static constexpr absl::string_view kIgnored[] = {
      "vt",    "vn",       "vp",       "o",    "s",          "mtllib",    "usemtl", "l",
      "p",     "cstype",   "deg",      "bmat", "step",       "curv",      "curv2",  "surf",
      "parm",  "trim",     "hole",     "scrv", "sp",         "end",       "con",    "mg",
      "bevel", "c_interp", "d_interp", "lod",  "shadow_obj", "trace_obj", "ctech",  "stech"};
  MeshFileSurvey s;
  // Group names in order of first appearance, and each face's index into them. Faces before
  // the first `g` are in OBJ's "default" group.
  std::vector<std::string> group_names;
  std::unordered_map<std::string, uint32_t> group_index;
  const auto intern = [&](std::string name) {
    auto [it, fresh] = group_index.try_emplace(name, uint32_t(group_names.size()));
    if (fresh) group_names.push_back(std::move(name));
    return it->second;
  };
  uint32_t group = intern(kObjDefaultGroup);
  bool any_group_statement = false;
  std::vector<uint32_t> face_group_index;
  Lines lines(data);
  absl::string_view line;
  while (lines.NextContent(&line)) {
    std::vector<absl::string_view> tok = Tokens(line);
    if (tok[0] == "v") {
      absl::Status st = CheckPosition(
          tok, 1, absl::StrCat("vertex ", s.vertices, " (line ", lines.number(), ")"));
      if (!st.ok()) return st;
      ++s.vertices;
    } else if (tok[0] == "g") {
      any_group_statement = true;
      group = intern(tok.size() == 1 ? std::string(kObjDefaultGroup)
                                     : absl::StrJoin(tok.begin() + 1, tok.end(), " "));
    } else if (tok[0] == "f") {
      const size_t f = s.faces++;
      face_group_index.push_back(group);
      const std::string where = absl::StrCat(" (line ", lines.number(), ")");
      if (tok.size() != 4) return Polygon(f, tok.size() - 1, where);
      int64_t idx[3];
      for (int i = 0; i < 3; ++i) {
        absl::string_view t = tok[i + 1].substr(0, tok[i + 1].find('/'));
        if (!ParseInt(t, &idx[i]) || idx[i] == 0)
          return Bad("face ", f, where, ": invalid vertex index '", tok[i + 1], "'");
        if (idx[i] < 0) idx[i] += int64_t(s.vertices) + 1;  // relative to the last vertex
        if (idx[i] <= 0)
          return Bad("face ", f, where, ": relative index '", tok[i + 1],
                     "' points before the first vertex");
      }
      // OpenMesh's OBJ reader drops such faces silently; report them instead.
      if (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2])
        return Bad("face ", f, where, " is degenerate: it repeats a vertex index");
    } else if (std::find(std::begin(kIgnored), std::end(kIgnored), tok[0]) == std::end(kIgnored)) {
      return Bad("line ", lines.number(), ": unknown OBJ statement '", tok[0], "'");
    }
  }
  if (any_group_statement) {
    const std::vector<uint32_t> ids = ObjGroupIds(group_names, &s.group_names);
    s.face_groups.reserve(face_group_index.size());
    for (uint32_t i : face_group_index) s.face_groups.push_back(ids[i]);
    if (std::all_of(s.face_groups.begin(), s.face_groups.end(),
                    [](uint32_t g) { return g == 0; })) {
      s.face_groups.clear();
      s.group_names.clear();
    }
  }
  return s;
}

// ---------------------------------------------------------------------------------- STL

absl::StatusOr<MeshFileSurvey> SurveyStlBinary(absl::string_view data, uint32_t n) {
  MeshFileSurvey s;
  s.vertices = 3 * size_t(n);
  s.faces = n;
  s.binary = true;
  for (uint32_t t = 0; t < n; ++t) {
    float c[9];  // the three corners, after the facet normal
    std::memcpy(c, data.data() + 84 + 50 * size_t(t) + 12, sizeof(c));
    for (int i = 0; i < 9; ++i)
      if (!std::isfinite(c[i]))
        return Bad("facet ", t, " corner ", i / 3, " has a non-finite coordinate ", c[i]);
    // OpenMesh merges equal corners and then drops the facet silently.
    const auto same = [&](int a, int b) {
      return c[3 * a] == c[3 * b] && c[3 * a + 1] == c[3 * b + 1] && c[3 * a + 2] == c[3 * b + 2];
    };
    if (same(0, 1) || same(1, 2) || same(0, 2))
      return Bad("facet ", t, " is degenerate: two of its corners coincide");
  }
  return s;
}

absl::StatusOr<MeshFileSurvey> SurveyStlAscii(absl::string_view data) {
  MeshFileSurvey s;
  Lines lines(data);
  absl::string_view line;
  bool ended = false;
  while (lines.Next(&line)) {
    std::vector<absl::string_view> tok = Tokens(line);
    if (tok.empty()) continue;
    const std::string key = absl::AsciiStrToLower(tok[0]);
    if (key == "endsolid") {
      ended = true;
      continue;
    }
    if (key == "solid" || key == "facet" || key == "endloop" || key == "endfacet") continue;
    if (key != "outer")
      return Bad("line ", lines.number(), ": unexpected '", tok[0], "' in ASCII STL");
    // OpenMesh reads the three lines after "outer loop" as the corners.
    const size_t t = s.faces++;
    double c[9];
    for (int k = 0; k < 3; ++k) {
      if (!lines.Next(&line))
        return Bad("truncated: the file ends inside facet ", t, " (line ", lines.number(), ")");
      tok = Tokens(line);
      const std::string where =
          absl::StrCat("facet ", t, " corner ", k, " (line ", lines.number(), ")");
      if (tok.empty() || absl::AsciiStrToLower(tok[0]) != "vertex")
        return Bad(where, ": expected 'vertex x y z'");
      absl::Status st = CheckPosition(tok, 1, where);
      if (!st.ok()) return st;
      for (int i = 0; i < 3; ++i) ParseDouble(tok[1 + i], &c[3 * k + i]);
    }
    s.vertices += 3;
    const auto same = [&](int a, int b) {
      for (int i = 0; i < 3; ++i)
        if (float(c[3 * a + i]) != float(c[3 * b + i])) return false;
      return true;
    };
    if (same(0, 1) || same(1, 2) || same(0, 2))
      return Bad("facet ", t, " (line ", lines.number(),
                 ") is degenerate: two of its corners coincide");
  }
  if (!ended) return Bad("truncated: ASCII STL without 'endsolid' (", s.faces, " facets read)");
  return s;
}

absl::StatusOr<MeshFileSurvey> SurveyStl(absl::string_view data) {
  // Same rule as OpenMesh: binary exactly when the size matches the triangle count.
  uint32_t n = 0;
  if (data.size() >= 84) {
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50 * uint64_t(n)) return SurveyStlBinary(data, n);
  }
  absl::string_view head = absl::StripLeadingAsciiWhitespace(data.substr(0, 512));
  if (absl::StartsWithIgnoreCase(head, "solid")) return SurveyStlAscii(data);
  if (data.size() < 84)
    return Bad("not an ASCII STL (no 'solid') and too short for a binary STL (", data.size(),
               " bytes, the header alone takes 84)");
  return Bad("binary STL size mismatch (truncated?): header announces ", n, " triangles (",
             84 + 50 * uint64_t(n), " bytes) but the file has ", data.size(), " bytes");
}

// ---------------------------------------------------------------------------------- PLY

enum class PlyType { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64, kNone };

PlyType ParsePlyType(absl::string_view t) {
  if (t == "char" || t == "int8") return PlyType::kI8;
  if (t == "uchar" || t == "uint8") return PlyType::kU8;
  if (t == "short" || t == "int16") return PlyType::kI16;
  if (t == "ushort" || t == "uint16") return PlyType::kU16;
  if (t == "int" || t == "int32") return PlyType::kI32;
  if (t == "uint" || t == "uint32") return PlyType::kU32;
  if (t == "float" || t == "float32") return PlyType::kF32;
  if (t == "double" || t == "float64") return PlyType::kF64;
  return PlyType::kNone;
}

size_t PlySize(PlyType t) {
  static constexpr size_t kSize[] = {1, 1, 2, 2, 4, 4, 4, 8, 0};
  return kSize[int(t)];
}

template <typename T>
double Load(const char* p, bool swap) {
  std::array<char, sizeof(T)> b;
  std::memcpy(b.data(), p, sizeof(T));
  if (swap) std::reverse(b.begin(), b.end());
  return double(std::bit_cast<T>(b));
}

double LoadPly(const char* p, PlyType t, bool swap) {
  switch (t) {
    case PlyType::kI8:
      return Load<int8_t>(p, swap);
    case PlyType::kU8:
      return Load<uint8_t>(p, swap);
    case PlyType::kI16:
      return Load<int16_t>(p, swap);
    case PlyType::kU16:
      return Load<uint16_t>(p, swap);
    case PlyType::kI32:
      return Load<int32_t>(p, swap);
    case PlyType::kU32:
      return Load<uint32_t>(p, swap);
    case PlyType::kF32:
      return Load<float>(p, swap);
    case PlyType::kF64:
      return Load<double>(p, swap);
    case PlyType::kNone:
      break;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kNone;
  PlyType count_type = PlyType::kNone;  // set for lists
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
};

// Reads the values of a PLY body, ASCII or binary, one at a time.
class PlyValues {
 public:
  PlyValues(absl::string_view body, bool ascii, bool swap)
      : body_(body), ascii_(ascii), swap_(swap) {}
  // False at the end of the data; sets error_ if a token is not a number.
  bool Next(PlyType t, double* out) {
    if (!ascii_) {
      const size_t n = PlySize(t);
      if (pos_ + n > body_.size()) return false;
      *out = LoadPly(body_.data() + pos_, t, swap_);
      pos_ += n;
      return true;
    }
    while (pos_ < body_.size() && absl::ascii_isspace(body_[pos_])) line_ += body_[pos_++] == '\n';
    if (pos_ >= body_.size()) return false;
    size_t end = pos_;
    while (end < body_.size() && !absl::ascii_isspace(body_[end])) ++end;
    token_ = body_.substr(pos_, end - pos_);
    pos_ = end;
    if (!ParseDouble(token_, out)) {
      error_ = true;
      return false;
    }
    return true;
  }
  bool error() const { return error_; }
  absl::string_view token() const { return token_; }
  // Where the reader stands, for messages.
  std::string Where(size_t header_lines) const {
    return ascii_ ? absl::StrCat(" (line ", header_lines + line_ + 1, ")")
                  : absl::StrCat(" (byte ", pos_, " of the body)");
  }

 private:
  absl::string_view body_;
  bool ascii_, swap_;
  size_t pos_ = 0, line_ = 0;
  bool error_ = false;
  absl::string_view token_;
};

absl::StatusOr<MeshFileSurvey> SurveyPly(absl::string_view data) {
  Lines lines(data);
  absl::string_view line;
  if (!lines.Next(&line) || absl::StripAsciiWhitespace(line) != "ply")
    return Bad("not a PLY file: the first line is not 'ply'");
  std::vector<PlyElement> elements;
  std::string format;
  bool header_done = false;
  while (lines.Next(&line)) {
    std::vector<absl::string_view> tok = Tokens(line);
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    const std::string where = absl::StrCat("PLY header line ", lines.number());
    if (tok[0] == "end_header") {
      header_done = true;
      break;
    }
    if (tok[0] == "format" && tok.size() >= 2) {
      format = std::string(tok[1]);
    } else if (tok[0] == "element" && tok.size() == 3) {
      int64_t n;
      if (!ParseInt(tok[2], &n) || n < 0) return Bad(where, ": bad element count '", tok[2], "'");
      elements.push_back({std::string(tok[1]), size_t(n), {}});
    } else if (tok[0] == "property" && !elements.empty() && tok.size() == 3 &&
               ParsePlyType(tok[1]) != PlyType::kNone) {
      elements.back().props.push_back({std::string(tok[2]), ParsePlyType(tok[1]), PlyType::kNone});
    } else if (tok[0] == "property" && !elements.empty() && tok.size() == 5 && tok[1] == "list" &&
               ParsePlyType(tok[2]) != PlyType::kNone && ParsePlyType(tok[3]) != PlyType::kNone) {
      elements.back().props.push_back(
          {std::string(tok[4]), ParsePlyType(tok[3]), ParsePlyType(tok[2])});
    } else {
      return Bad(where, ": cannot parse '", line, "'");
    }
  }
  if (!header_done) return Bad("truncated: PLY header without 'end_header'");
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian" && format != "binary_big_endian")
    return Bad("unknown PLY format '", format, "'");
  const bool swap = format == (std::endian::native == std::endian::little ? "binary_big_endian"
                                                                          : "binary_little_endian");
  MeshFileSurvey s;
  s.binary = !ascii;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") s.vertices = e.count;
    if (e.name == "face") s.faces = e.count;
  }
  const size_t header_lines = lines.number();
  PlyValues values(data.substr(lines.offset()), ascii, swap);
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    // What each face property carries (face_data.h): kGroup, a field index, or kOther.
    constexpr int kOther = -2, kGroup = -1;
    std::vector<int> role(e.props.size(), kOther);
    bool groups = false;
    if (is_face) {
      s.face_fields.clear();
      for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        for (size_t j = 0; j < k; ++j)
          if (e.props[j].name == p.name)
            return Bad("PLY header: face property '", p.name, "' is declared twice");
        const bool scalar = p.count_type == PlyType::kNone;
        const bool floating = p.type == PlyType::kF32 || p.type == PlyType::kF64;
        if (p.name == kPlyGroupProperty) {
          if (!scalar || floating)
            return Bad("PLY header: face property '", kPlyGroupProperty,
                       "' must be a scalar of an integer type (one group id per face)");
          role[k] = kGroup;
          groups = true;
        } else if (scalar && floating && IsPlyFieldName(p.name)) {
          role[k] = int(s.face_fields.size());
          s.face_fields.push_back({p.name, {}});
        }
      }
      if (s.face_fields.size() > kMaxFaceFields) {
        std::vector<std::string> names;
        for (const FaceField& f : s.face_fields) names.push_back(f.name);
        return Bad("PLY header: ", names.size(), " float face properties (",
                   absl::StrJoin(names, ", "), ") but femsimp carries at most ", kMaxFaceFields,
                   " face fields");
      }
      // The header's count is not trusted for memory: every face takes at least a byte.
      const size_t expected = std::min(e.count, data.size());
      s.face_groups.clear();
      if (groups) s.face_groups.reserve(expected);
      for (FaceField& f : s.face_fields) f.values.reserve(expected);
    }
    for (size_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        const auto fail = [&]() {
          if (values.error())
            return Bad(e.name, " ", i, values.Where(header_lines), ": cannot parse '",
                       values.token(), "' as a number");
          return Bad("truncated: header announces ", s.vertices, " vertices and ", s.faces,
                     " faces but the data ends in ", e.name, " ", i, values.Where(header_lines));
        };
        double v;
        if (p.count_type == PlyType::kNone) {
          if (!values.Next(p.type, &v)) return fail();
          if (is_vertex && (p.name == "x" || p.name == "y" || p.name == "z") && !FiniteAsFloat(v))
            return Bad("vertex ", i, values.Where(header_lines), ": coordinate ", p.name, " = ", v,
                       " is not a finite float");
          if (role[k] == kGroup) {
            // ASCII values are not bound by the declared type.
            if (!(v >= 0 && v <= double(std::numeric_limits<uint32_t>::max()) &&
                  v == std::floor(v)))
              return Bad("face ", i, values.Where(header_lines), ": group ", v,
                         " is not an integer in [0, 2^32)");
            s.face_groups.push_back(uint32_t(v));
          } else if (role[k] >= 0) {
            if (!FiniteAsFloat(v))
              return Bad("face ", i, values.Where(header_lines), ": field '", p.name, "' = ", v,
                         " is not a finite float");
            s.face_fields[size_t(role[k])].values.push_back(float(v));
          }
          continue;
        }
        double n;
        if (!values.Next(p.count_type, &n)) return fail();
        if (!(n >= 0 && n <= 1e9))  // also keeps the size_t conversion below defined
          return Bad(e.name, " ", i, values.Where(header_lines), ": bad list length ", n);
        const bool indices = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (indices && n != 3) return Polygon(i, size_t(n), values.Where(header_lines));
        for (size_t k = 0; k < size_t(n); ++k) {
          if (!values.Next(p.type, &v)) return fail();
          if (indices && v < 0)
            return Bad("face ", i, values.Where(header_lines), " has a negative vertex index ", v);
        }
      }
    }
  }
  if (std::all_of(s.face_groups.begin(), s.face_groups.end(), [](uint32_t g) { return g == 0; }))
    s.face_groups.clear();
  return s;
}

}  // namespace

absl::StatusOr<MeshFileSurvey> SurveyMeshFile(absl::string_view ext, absl::string_view data) {
  if (ext == ".off") return SurveyOff(data);
  if (ext == ".obj") return SurveyObj(data);
  if (ext == ".stl") return SurveyStl(data);
  if (ext == ".ply") return SurveyPly(data);
  return Bad("no survey for extension '", ext, "'");
}

}  // namespace femsimp
