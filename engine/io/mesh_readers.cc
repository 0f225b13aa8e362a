#include "engine/io/mesh_readers.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "absl/hash/hash.h"
#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "engine/id_index.h"
#include "engine/io/msh.h"
#include "engine/io/polygons.h"
#include "engine/io/reader_util.h"
#include "engine/local_origin.h"

namespace femsimp {
namespace {

using io_internal::Bad;
using io_internal::Excerpt;
using io_internal::FiniteAsFloat;
using io_internal::LoadBytes;
using io_internal::ParseCoordinate;
using io_internal::ParseDouble;
using io_internal::ParseInt;

// What a reader hands on: the soup, and for OBJ and ASCII STL the line of each face, for the
// messages of the check that follows the parse.
struct Reading {
  ParsedMeshFile file;
  // The coordinates of the text formats and PLY, x, y, z per vertex (ASCII STL: per corner), kept
  // in double until the part is placed at its local origin (Localize).
  std::vector<double> xyz;
  bool weld_corners = false;  // ASCII STL: xyz holds corners, welded once they are floats
  std::vector<size_t> face_lines;
  std::vector<PolygonFace> polygons;  // faces of more corners than three, cut after the parse
};

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

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// The blank-separated tokens of a line, into `out` (reused from line to line, so that reading a
// line allocates nothing).
void Split(absl::string_view line, std::vector<absl::string_view>* out) {
  out->clear();
  size_t i = 0;
  while (true) {
    while (i < line.size() && IsBlank(line[i])) ++i;
    if (i == line.size()) return;
    const size_t start = i;
    while (i < line.size() && !IsBlank(line[i])) ++i;
    out->push_back(line.substr(start, i - start));
  }
}

// Parses tok[first..first+2] as a finite vertex position and appends it; `where()` names the
// vertex (called only for a message, so that a good vertex formats nothing).
template <typename Where>
absl::Status AddPosition(const std::vector<absl::string_view>& tok, size_t first, Where where,
                         std::vector<double>* xyz) {
  if (tok.size() < first + 3)
    return Bad(where(), ": expected 3 coordinates, found ", tok.size() - first);
  for (size_t i = first; i < first + 3; ++i) {
    double x;
    if (!ParseCoordinate(tok[i], &x))
      return Bad(where(), ": cannot parse '", Excerpt(tok[i]), "' as a number");
    if (!FiniteAsFloat(x))
      return Bad(where(), ": coordinate '", Excerpt(tok[i]), "' is not a finite float");
    xyz->push_back(x);
  }
  return absl::OkStatus();
}

// Whether a vertex index fits the soup's 32 bits (whether it names a vertex is checked once the
// vertex count is known).
bool FitsIndex(int64_t i) { return i >= 0 && i <= int64_t{std::numeric_limits<uint32_t>::max()}; }

absl::Status OutOfRange(size_t face, absl::string_view where, int64_t index, int64_t vertices) {
  return Bad("face ", face, where, " references vertex ", index, " but the file has ", vertices,
             " vertices");
}

// A face of 3 to kMaxPolygonCorners corners is read (polygons.h); others are refused.
bool Readable(int64_t corners) { return corners >= 3 && corners <= int64_t{kMaxPolygonCorners}; }

absl::Status Polygon(size_t face, size_t corners, absl::string_view where) {
  if (corners < 3) return Bad("face ", face, where, " has ", corners, " vertices: a face needs 3");
  return Bad("face ", face, where, " has ", corners, " vertices: femsimp cuts polygons of up to ",
             kMaxPolygonCorners, " corners into triangles; triangulate this one first");
}

// Notes a face of more than three corners for TriangulatePolygons.
void NotePolygon(size_t face, int64_t corners, Reading* out) {
  if (corners > 3) out->polygons.push_back({face, uint32_t(corners)});
}

// ---------------------------------------------------------------------------------- OFF

// Binary OFF: three 32-bit counts, then per vertex 3 floats (and what the header's prefixes
// add: normal, colour, texture coordinates), per face a count and the indices. Little-endian as
// OpenMesh writes it; big-endian (the format's own definition) when the counts only fit so.
absl::Status ParseOffBinary(absl::string_view rest, absl::string_view key, Reading* out) {
  if (rest.size() < 12) return Bad("binary OFF: file ends inside the counts");
  bool swap = false;
  uint32_t nv = LoadBytes<uint32_t>(rest.data(), false);
  uint32_t nf = LoadBytes<uint32_t>(rest.data() + 4, false);
  if (uint64_t(nv) * 12 > rest.size()) {
    swap = true;
    nv = LoadBytes<uint32_t>(rest.data(), true);
    nf = LoadBytes<uint32_t>(rest.data() + 4, true);
  }
  const size_t extra = (absl::StartsWith(key, "ST") ? 8 : 0) +
                       (absl::StrContains(key, "C") ? 12 : 0) +
                       (absl::StrContains(key, "N") ? 12 : 0);
  const uint64_t vertex_bytes = 12 + extra;
  const uint64_t need = 12 + uint64_t(nv) * vertex_bytes + uint64_t(nf) * 16;
  if (need > rest.size())
    return Bad("binary OFF truncated: header announces ", nv, " vertices and ", nf,
               " faces (at least ", need, " bytes of data) but only ", rest.size(),
               " bytes follow the header");
  RawMesh& mesh = out->file.mesh;
  mesh.positions.resize(3 * size_t(nv));
  const char* p = rest.data() + 12;
  for (size_t v = 0; v < nv; ++v, p += vertex_bytes)
    for (int i = 0; i < 3; ++i) {
      const float x = LoadBytes<float>(p + 4 * i, swap);
      if (!std::isfinite(x))
        return Bad("vertex ", v, " (byte ", p - rest.data(), " after the header): coordinate ", i,
                   " = ", x, " is not a finite float");
      mesh.positions[3 * v + i] = x;
    }
  mesh.triangles.reserve(3 * size_t(nf));
  for (size_t f = 0; f < nf; ++f) {
    const auto where = [&] {
      return absl::StrCat(" (byte ", p - rest.data(), " after the header)");
    };
    if (p + 4 > rest.data() + rest.size())
      return Bad("binary OFF truncated: the file ends inside face ", f, where());
    const int32_t n = LoadBytes<int32_t>(p, swap);
    if (!Readable(n)) return Polygon(f, size_t(std::max(n, 0)), where());
    if (size_t(rest.data() + rest.size() - p) < 4 + 4 * size_t(n))
      return Bad("binary OFF truncated: the file ends inside face ", f, where());
    NotePolygon(f, n, out);
    for (int i = 1; i <= n; ++i) {
      const int32_t idx = LoadBytes<int32_t>(p + 4 * i, swap);
      if (idx < 0) return Bad("face ", f, where(), " has a negative vertex index ", idx);
      if (uint32_t(idx) >= nv) return OutOfRange(f, where(), uint32_t(idx), nv);
      mesh.triangles.push_back(uint32_t(idx));
    }
    p += 4 + 4 * size_t(n);
  }
  return absl::OkStatus();
}

absl::Status ParseOff(absl::string_view data, Reading* out) {
  Lines lines(data);
  absl::string_view line;
  if (!lines.NextContent(&line)) return Bad("no OFF header");
  std::vector<absl::string_view> tok;
  Split(line, &tok);
  const absl::string_view key = tok[0];
  // OFF with optional ST (texture), C (colour), N (normal) prefixes; 4OFF/nOFF are not 3D.
  if (!absl::EndsWith(key, "OFF") || absl::StrContains(key, "4") || key[0] == 'n')
    return Bad("line ", lines.number(), ": expected an OFF header, found '", Excerpt(key), "'");
  if (tok.size() > 1 && tok[1] == "BINARY")
    return ParseOffBinary(data.substr(lines.offset()), key, out);
  tok.erase(tok.begin());
  if (tok.empty()) {
    if (!lines.NextContent(&line)) return Bad("OFF header has no vertex and face counts");
    Split(line, &tok);
  }
  int64_t nv, nf;
  if (tok.size() < 2 || !ParseInt(tok[0], &nv) || !ParseInt(tok[1], &nf) || nv < 0 || nf < 0)
    return Bad("line ", lines.number(), ": expected vertex and face counts, found '", Excerpt(line),
               "'");
  const auto truncated = [&](absl::string_view what, size_t got) {
    return Bad("truncated: header announces ", nv, " vertices and ", nf,
               " faces but the file ends after ", got, " ", what, " (line ", lines.number(), ")");
  };
  RawMesh& mesh = out->file.mesh;
  // The counts are not trusted for memory: every line takes at least two bytes.
  out->xyz.reserve(3 * std::min<size_t>(size_t(nv), data.size() / 2));
  mesh.triangles.reserve(3 * std::min<size_t>(size_t(nf), data.size() / 2));
  for (size_t v = 0; v < size_t(nv); ++v) {
    if (!lines.NextContent(&line)) return truncated("vertices", v);
    Split(line, &tok);
    absl::Status st = AddPosition(
        tok, 0, [&] { return absl::StrCat("vertex ", v, " (line ", lines.number(), ")"); },
        &out->xyz);
    if (!st.ok()) return st;
  }
  for (size_t f = 0; f < size_t(nf); ++f) {
    if (!lines.NextContent(&line)) return truncated("faces", f);
    Split(line, &tok);
    const auto where = [&] { return absl::StrCat(" (line ", lines.number(), ")"); };
    int64_t n;
    if (!ParseInt(tok[0], &n))
      return Bad("face ", f, where(), ": cannot parse '", Excerpt(tok[0]), "' as a vertex count");
    if (!Readable(n)) return Polygon(f, size_t(std::max<int64_t>(n, 0)), where());
    if (tok.size() < size_t(n) + 1)
      return Bad("face ", f, where(), ": expected ", n, " vertex indices");
    NotePolygon(f, n, out);
    for (size_t i = 1; i <= size_t(n); ++i) {
      int64_t idx;
      if (!ParseInt(tok[i], &idx))
        return Bad("face ", f, where(), ": cannot parse '", Excerpt(tok[i]), "' as a vertex index");
      if (idx < 0) return Bad("face ", f, where(), " has a negative vertex index ", idx);
      if (!FitsIndex(idx)) return Bad("face ", f, where(), ": vertex index ", idx, " is too large");
      if (idx >= nv) return OutOfRange(f, where(), idx, nv);
      mesh.triangles.push_back(uint32_t(idx));
    }
  }
  return absl::OkStatus();
}

// Face groups named in the file (OBJ's `g`, ASCII STL's `solid`): the distinct names in order of
// first appearance, and each face's index into them, until the ids are known (ObjGroupIds).
class NamedFaceGroups {
 public:
  uint32_t Intern(std::string name) {
    auto [it, fresh] = index_.try_emplace(name, uint32_t(names_.size()));
    if (fresh) names_.push_back(std::move(name));
    return it->second;
  }
  void AddFace(uint32_t name_index) { faces_.push_back(name_index); }
  size_t distinct_names() const { return names_.size(); }

  // The faces' group ids and the names that need keeping; none when every face is in group 0.
  void AssignTo(ParsedMeshFile* file) const {
    const std::vector<uint32_t> ids = ObjGroupIds(names_, &file->group_names);
    RawMesh& mesh = file->mesh;
    mesh.face_groups.reserve(faces_.size());
    for (uint32_t i : faces_) mesh.face_groups.push_back(ids[i]);
    if (!HasFaceGroups(mesh)) {
      mesh.face_groups.clear();
      file->group_names.clear();
    }
  }

 private:
  std::vector<std::string> names_;
  std::unordered_map<std::string, uint32_t> index_;
  std::vector<uint32_t> faces_;
};

// ---------------------------------------------------------------------------------- OBJ

// OBJ continues a statement on the next line after a trailing backslash.
bool EndsInContinuation(absl::string_view line) {
  return absl::EndsWith(absl::StripTrailingAsciiWhitespace(line), "\\");
}

absl::Status ParseObj(absl::string_view data, Reading* out) {
  static constexpr absl::string_view kIgnored[] = {
      "vt",    "vn",       "vp",       "o",    "s",          "mtllib",    "usemtl", "l",
      "p",     "cstype",   "deg",      "bmat", "step",       "curv",      "curv2",  "surf",
      "parm",  "trim",     "hole",     "scrv", "sp",         "end",       "con",    "mg",
      "bevel", "c_interp", "d_interp", "lod",  "shadow_obj", "trace_obj", "ctech",  "stech"};
  RawMesh& mesh = out->file.mesh;
  // Faces before the first `g` are in OBJ's "default" group.
  NamedFaceGroups groups;
  uint32_t group = groups.Intern(kObjDefaultGroup);
  bool any_group_statement = false;
  Lines lines(data);
  absl::string_view line;
  std::vector<absl::string_view> tok;
  std::string joined;  // a statement continued over lines ending in a backslash
  while (lines.NextContent(&line)) {
    if (EndsInContinuation(line)) {
      joined.clear();
      absl::string_view part = line;
      while (EndsInContinuation(part)) {
        absl::string_view body = absl::StripTrailingAsciiWhitespace(part);
        body.remove_suffix(1);
        absl::StrAppend(&joined, body, " ");
        if (!lines.Next(&part)) part = {};
      }
      absl::StrAppend(&joined, part);
      line = joined;
    }
    Split(line, &tok);
    if (tok.empty()) continue;
    if (tok[0] == "v") {
      absl::Status st = AddPosition(
          tok, 1,
          [&] {
            return absl::StrCat("vertex ", out->xyz.size() / 3, " (line ", lines.number(), ")");
          },
          &out->xyz);
      if (!st.ok()) return st;
    } else if (tok[0] == "g") {
      any_group_statement = true;
      group = groups.Intern(tok.size() == 1 ? std::string(kObjDefaultGroup)
                                            : absl::StrJoin(tok.begin() + 1, tok.end(), " "));
    } else if (tok[0] == "f") {
      const size_t f = out->face_lines.size();
      out->face_lines.push_back(lines.number());
      groups.AddFace(group);
      const auto where = [&] { return absl::StrCat(" (line ", lines.number(), ")"); };
      const int64_t n = int64_t(tok.size()) - 1;
      if (!Readable(n)) return Polygon(f, size_t(n), where());
      NotePolygon(f, n, out);
      for (int64_t i = 1; i <= n; ++i) {
        int64_t idx;
        absl::string_view t = tok[i].substr(0, tok[i].find('/'));
        if (!ParseInt(t, &idx) || idx == 0)
          return Bad("face ", f, where(), ": invalid vertex index '", Excerpt(tok[i]), "'");
        if (idx < 0) idx += int64_t(out->xyz.size() / 3) + 1;  // relative to the last vertex
        if (idx <= 0)
          return Bad("face ", f, where(), ": relative index '", Excerpt(tok[i]),
                     "' points before the first vertex");
        if (!FitsIndex(idx - 1))
          return Bad("face ", f, where(), ": vertex index '", Excerpt(tok[i]), "' is too large");
        mesh.triangles.push_back(uint32_t(idx - 1));
      }
    } else if (std::find(std::begin(kIgnored), std::end(kIgnored), tok[0]) == std::end(kIgnored)) {
      return Bad("line ", lines.number(), ": unknown OBJ statement '", Excerpt(tok[0]), "'");
    }
  }
  if (any_group_statement) groups.AssignTo(&out->file);
  return absl::OkStatus();
}

// ---------------------------------------------------------------------------------- STL

// STL stores each facet's corners; equal corners become one vertex, numbered in order of first
// appearance (0.0 and -0.0 are equal, as they were to OpenMesh's STL reader).
class Welder {
 public:
  explicit Welder(RawMesh* mesh, size_t facets = 0)
      : mesh_(mesh), index_(facets / 2, KeyOfVertex{mesh}) {
    mesh_->positions.reserve(3 * facets / 2);
    mesh_->triangles.reserve(3 * facets);
  }
  void AddCorner(const float* p) {
    const Key key = KeyOf(p);
    // Neighbouring facets share corners: a small table of recent corners answers most of them
    // from cache before the index's lookup misses it.
    Recent& recent = recent_[absl::HashOf(key) & (kRecent - 1)];
    if (recent.id != kNone && recent.key == key) {
      mesh_->triangles.push_back(recent.id);
      return;
    }
    // The position goes in first: the index reads it back when it grows.
    const size_t fresh = mesh_->num_vertices();
    mesh_->positions.insert(mesh_->positions.end(), p, p + 3);
    const uint32_t v = index_.FindOrInsert(key, uint32_t(fresh));
    if (v != fresh) mesh_->positions.resize(3 * fresh);
    mesh_->triangles.push_back(v);
    recent = {key, v};
  }

 private:
  using Key = std::array<uint32_t, 3>;
  static Key KeyOf(const float* p) {
    Key key;
    for (int i = 0; i < 3; ++i) key[i] = std::bit_cast<uint32_t>(p[i] == 0.0f ? 0.0f : p[i]);
    return key;
  }
  struct KeyOfVertex {
    const RawMesh* mesh;
    Key operator()(uint32_t v) const { return KeyOf(&mesh->positions[3 * size_t(v)]); }
  };

  static constexpr size_t kRecent = 4096;
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  struct Recent {
    Key key;
    uint32_t id = kNone;
  };

  RawMesh* mesh_;
  IdIndex<Key, KeyOfVertex> index_;
  std::vector<Recent> recent_ = std::vector<Recent>(kRecent);
};

absl::Status ParseStlBinary(absl::string_view data, uint32_t n, Reading* out) {
  Welder welder(&out->file.mesh, n);
  for (uint32_t t = 0; t < n; ++t) {
    float c[9];  // the three corners, after the facet normal
    std::memcpy(c, data.data() + 84 + 50 * size_t(t) + 12, sizeof(c));
    for (int i = 0; i < 9; ++i)
      if (!std::isfinite(c[i]))
        return Bad("facet ", t, " corner ", i / 3, " has a non-finite coordinate ", c[i]);
    for (int k = 0; k < 3; ++k) welder.AddCorner(&c[3 * k]);
  }
  return absl::OkStatus();
}

absl::Status ParseStlAscii(absl::string_view data, Reading* out) {
  out->weld_corners = true;
  Lines lines(data);
  absl::string_view line;
  std::vector<absl::string_view> tok;
  bool ended = false;
  // Each `solid NAME` is a face group (one solid per CAD face or boundary patch, as gmsh, Salome
  // and CFD/FE pre-processors write them); an unnamed solid is OBJ's "default".
  NamedFaceGroups solids;
  uint32_t solid = 0;
  while (lines.Next(&line)) {
    Split(line, &tok);
    if (tok.empty()) continue;
    const auto is = [&](absl::string_view word) { return absl::EqualsIgnoreCase(tok[0], word); };
    if (is("endsolid")) {
      ended = true;
      continue;
    }
    if (is("solid")) {
      absl::string_view name = absl::StripAsciiWhitespace(line);
      name = absl::StripLeadingAsciiWhitespace(name.substr(tok[0].size()));
      solid = solids.Intern(name.empty() ? std::string(kObjDefaultGroup) : std::string(name));
      continue;
    }
    if (is("facet") || is("endloop") || is("endfacet")) continue;
    if (!is("outer"))
      return Bad("line ", lines.number(), ": unexpected '", Excerpt(tok[0]), "' in ASCII STL");
    // The three lines after "outer loop" are the corners.
    const size_t t = out->face_lines.size();
    for (int k = 0; k < 3; ++k) {
      if (!lines.Next(&line))
        return Bad("truncated: the file ends inside facet ", t, " (line ", lines.number(), ")");
      Split(line, &tok);
      const auto where = [&] {
        return absl::StrCat("facet ", t, " corner ", k, " (line ", lines.number(), ")");
      };
      if (tok.empty() || !absl::EqualsIgnoreCase(tok[0], "vertex"))
        return Bad(where(), ": expected 'vertex x y z'");
      if (absl::Status st = AddPosition(tok, 1, where, &out->xyz); !st.ok()) return st;
    }
    out->face_lines.push_back(lines.number());
    solids.AddFace(solid);
  }
  // Some writers leave 'endsolid' out; a file cut between two facets looks the same, so its
  // facets are read and the warning says both.
  if (!ended)
    out->file.warnings.push_back(absl::StrCat(
        "ASCII STL: no 'endsolid' (the file ends at line ", lines.number(), " after ",
        out->face_lines.size(), " whole facets): read them all; was the file cut short?"));
  // One name is the file's, not a grouping.
  if (solids.distinct_names() > 1) solids.AssignTo(&out->file);
  return absl::OkStatus();
}

// Whether an STL that begins with "solid" is text. CAD exporters often start a binary file's
// free 80-byte header with "solid" too; text STL never holds a NUL byte, while a binary one does
// within its first facets (the count's high byte under 2^24 facets, each facet's attribute word,
// zero normal components).
bool StlIsText(absl::string_view data) {
  constexpr size_t kLooked = 84 + 4 * 50;
  return data.substr(0, kLooked).find('\0') == absl::string_view::npos;
}

// A binary STL whose facet count does not match its size. Writers that stream and never seek
// back leave the count 0; others pad the file. The facets a count announces are read and
// whatever follows them left out; a count of 0 reads every whole facet; a count the bytes
// cannot hold is a truncated file. Each is a warning, never silent.
absl::Status ParseStlBinaryMismatched(absl::string_view data, uint32_t n, Reading* out) {
  const uint64_t whole = (data.size() - 84) / 50;
  const uint64_t rest = (data.size() - 84) % 50;
  if (n > whole)
    return Bad("binary STL size mismatch (truncated?): header announces ", n, " triangles (",
               84 + 50 * uint64_t(n), " bytes) but the file has ", data.size(), " bytes (", whole,
               " whole facets)");
  if (n == 0) {
    if (whole > std::numeric_limits<uint32_t>::max())
      return Bad("binary STL: the header announces 0 facets and the file holds ", whole,
                 ", more than 2^32 - 1");
    n = uint32_t(whole);
    out->file.warnings.push_back(absl::StrCat(
        "binary STL: the header announces 0 facets but the file holds ", whole, "; read them all",
        rest ? absl::StrCat(" and left out the ", rest, " bytes after them") : ""));
  } else {
    out->file.warnings.push_back(
        absl::StrCat("binary STL: left out the ", data.size() - 84 - 50 * uint64_t(n),
                     " bytes after the ", n, " facets the header announces"));
  }
  return ParseStlBinary(data, n, out);
}

absl::Status ParseStl(absl::string_view data, Reading* out) {
  // Binary exactly when the size matches the triangle count (OpenMesh's rule), whatever the
  // header says; then text when it begins with "solid" and is text.
  uint32_t n = 0;
  if (data.size() >= 84) {
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50 * uint64_t(n)) return ParseStlBinary(data, n, out);
  }
  absl::string_view head = absl::StripLeadingAsciiWhitespace(data.substr(0, 512));
  const bool solid = absl::StartsWithIgnoreCase(head, "solid");
  if (solid && StlIsText(data)) return ParseStlAscii(data, out);
  if (data.size() < 84)
    return Bad("not an ASCII STL (", solid ? "it holds NUL bytes" : "no 'solid'",
               ") and too short for a binary STL (", data.size(),
               " bytes, the header alone takes 84)");
  return ParseStlBinaryMismatched(data, n, out);
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

double LoadPly(const char* p, PlyType t, bool swap) {
  switch (t) {
    case PlyType::kI8:
      return LoadBytes<int8_t>(p, swap);
    case PlyType::kU8:
      return LoadBytes<uint8_t>(p, swap);
    case PlyType::kI16:
      return LoadBytes<int16_t>(p, swap);
    case PlyType::kU16:
      return LoadBytes<uint16_t>(p, swap);
    case PlyType::kI32:
      return LoadBytes<int32_t>(p, swap);
    case PlyType::kU32:
      return LoadBytes<uint32_t>(p, swap);
    case PlyType::kF32:
      return LoadBytes<float>(p, swap);
    case PlyType::kF64:
      return LoadBytes<double>(p, swap);
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
    return NextToken() && Result(ParseDouble(token_, out));
  }
  // A coordinate: ASCII text parsed as a double (beyond its range: an infinity), a binary value
  // of any type converted to double.
  bool NextCoordinate(PlyType t, double* out) {
    if (ascii_) return NextToken() && Result(ParseCoordinate(token_, out));
    return Next(t, out);
  }
  bool ascii() const { return ascii_; }
  bool swap() const { return swap_; }
  // The binary data not read yet, and skipping what a caller read of it.
  absl::string_view rest() const { return body_.substr(pos_); }
  void Skip(size_t n) { pos_ += n; }
  bool error() const { return error_; }
  absl::string_view token() const { return token_; }
  // Where the reader stands, for messages.
  std::string Where(size_t header_lines) const {
    return ascii_ ? absl::StrCat(" (line ", header_lines + line_ + 1, ")")
                  : absl::StrCat(" (byte ", pos_, " of the body)");
  }

 private:
  bool NextToken() {
    while (pos_ < body_.size() && absl::ascii_isspace(body_[pos_])) line_ += body_[pos_++] == '\n';
    if (pos_ >= body_.size()) return false;
    size_t end = pos_;
    while (end < body_.size() && !absl::ascii_isspace(body_[end])) ++end;
    token_ = body_.substr(pos_, end - pos_);
    pos_ = end;
    return true;
  }
  bool Result(bool ok) {
    error_ = !ok;
    return ok;
  }

  absl::string_view body_;
  bool ascii_, swap_;
  size_t pos_ = 0, line_ = 0;
  bool error_ = false;
  absl::string_view token_;
};

// What each property of a PLY element carries (ParsePly): a coordinate (0, 1, 2 for x, y, z),
// a face's corners, its group, a field index (face_data.h), or nothing femsimp keeps.
constexpr int kPlyOther = -3, kPlyCorners = -2, kPlyGroup = -1;

// A vertex's coordinates: into `coordinates` (double, placed at the local origin later), or, where
// the file's coordinates are floats (null), straight into the mesh's positions.
void AppendVertex(const double xyz[3], std::vector<double>* coordinates, RawMesh& mesh) {
  if (coordinates != nullptr) {
    coordinates->insert(coordinates->end(), xyz, xyz + 3);
  } else {
    for (int k = 0; k < 3; ++k) mesh.positions.push_back(static_cast<float>(xyz[k]));
  }
}

// A binary element whose records all have one size (scalars, and triangles as the corner list),
// read straight off the bytes: no per-value dispatch through PlyValues. Returns how many records
// it read. It stops at the first record that is not plain (a list of another length, a value the
// reader refuses, the end of the data) without keeping any of it, so that the general loop reads
// that record and words any refusal exactly as it always has.
size_t ReadPlyBinaryRecords(const PlyElement& e, const std::vector<int>& role, bool is_vertex,
                            PlyValues& values, RawMesh& mesh, std::vector<double>* coordinates) {
  struct Slot {
    size_t offset;
    PlyType type;
    int role;
  };
  std::vector<Slot> slots;
  size_t stride = 0;
  for (size_t k = 0; k < e.props.size(); ++k) {
    const PlyProperty& p = e.props[k];
    if (p.count_type == PlyType::kNone) {
      if (role[k] != kPlyOther) slots.push_back({stride, p.type, role[k]});
      stride += PlySize(p.type);
    } else if (role[k] == kPlyCorners) {
      slots.push_back({stride, p.count_type, kPlyCorners});
      stride += PlySize(p.count_type) + 3 * PlySize(p.type);
    } else {
      return 0;  // a list of any length besides the corners: records differ in size
    }
  }
  const PlyType index_type = [&] {
    for (const PlyProperty& p : e.props)
      if (p.count_type != PlyType::kNone) return p.type;
    return PlyType::kNone;
  }();
  const bool swap = values.swap();
  const absl::string_view data = values.rest();
  const size_t records = stride == 0 ? 0 : std::min(e.count, data.size() / stride);
  size_t i = 0;
  for (; i < records; ++i) {
    const char* r = data.data() + i * stride;
    double xyz[3] = {0, 0, 0};
    float fields[kMaxFaceFields] = {};
    uint32_t corners[3] = {0, 0, 0}, group = 0;
    bool plain = true;
    for (const Slot& s : slots) {
      const char* p = r + s.offset;
      if (is_vertex) {
        if (s.role < 0) continue;
        xyz[s.role] = LoadPly(p, s.type, swap);
        plain = plain && FiniteAsFloat(xyz[s.role]);
      } else if (s.role == kPlyCorners) {
        plain = plain && LoadPly(p, s.type, swap) == 3;
        p += PlySize(s.type);
        for (int c = 0; c < 3; ++c, p += PlySize(index_type)) {
          const double v = LoadPly(p, index_type, swap);
          plain = plain && v >= 0 && v == std::floor(v) &&
                  v <= double(std::numeric_limits<uint32_t>::max());
          corners[c] = plain ? uint32_t(v) : 0;
        }
      } else if (s.role == kPlyGroup) {
        const double v = LoadPly(p, s.type, swap);
        plain = plain && v >= 0 && v <= double(std::numeric_limits<uint32_t>::max()) &&
                v == std::floor(v);
        group = plain ? uint32_t(v) : 0;
      } else {
        const double v = LoadPly(p, s.type, swap);
        plain = plain && FiniteAsFloat(v);
        fields[s.role] = float(v);
      }
    }
    if (!plain) break;
    if (is_vertex) {
      AppendVertex(xyz, coordinates, mesh);
      continue;
    }
    mesh.triangles.insert(mesh.triangles.end(), corners, corners + 3);
    for (const Slot& s : slots)
      if (s.role == kPlyGroup) {
        mesh.face_groups.push_back(group);
      } else if (s.role >= 0) {
        mesh.face_fields[size_t(s.role)].values.push_back(fields[s.role]);
      }
  }
  values.Skip(i * stride);
  return i;
}

absl::Status ParsePly(absl::string_view data, Reading* out) {
  Lines lines(data);
  absl::string_view line;
  if (!lines.Next(&line) || absl::StripAsciiWhitespace(line) != "ply")
    return Bad("not a PLY file: the first line is not 'ply'");
  std::vector<PlyElement> elements;
  std::string format;
  bool header_done = false;
  std::vector<absl::string_view> tok;
  while (lines.Next(&line)) {
    Split(line, &tok);
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
      if (!ParseInt(tok[2], &n) || n < 0)
        return Bad(where, ": bad element count '", Excerpt(tok[2]), "'");
      elements.push_back({std::string(tok[1]), size_t(n), {}});
    } else if (tok[0] == "property" && !elements.empty() && tok.size() == 3 &&
               ParsePlyType(tok[1]) != PlyType::kNone) {
      elements.back().props.push_back({std::string(tok[2]), ParsePlyType(tok[1]), PlyType::kNone});
    } else if (tok[0] == "property" && !elements.empty() && tok.size() == 5 && tok[1] == "list" &&
               ParsePlyType(tok[2]) != PlyType::kNone && ParsePlyType(tok[3]) != PlyType::kNone) {
      elements.back().props.push_back(
          {std::string(tok[4]), ParsePlyType(tok[3]), ParsePlyType(tok[2])});
    } else {
      return Bad(where, ": cannot parse '", Excerpt(line), "'");
    }
  }
  if (!header_done)
    return Bad("truncated: PLY header without 'end_header' (the file ends at line ", lines.number(),
               ")");
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian" && format != "binary_big_endian")
    return Bad("unknown PLY format '", Excerpt(format), "'");
  const bool swap = format == (std::endian::native == std::endian::little ? "binary_big_endian"
                                                                          : "binary_little_endian");
  size_t announced_vertices = 0, announced_faces = 0;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") announced_vertices = e.count;
    if (e.name == "face") announced_faces = e.count;
  }
  RawMesh& mesh = out->file.mesh;
  // Binary float coordinates are kept as floats (moved to the local origin exactly, Localize):
  // no copy of them in double.
  const bool float_coordinates =
      !ascii && std::all_of(elements.begin(), elements.end(), [](const PlyElement& e) {
        return e.name != "vertex" ||
               std::all_of(e.props.begin(), e.props.end(), [](const PlyProperty& p) {
                 return !(p.name == "x" || p.name == "y" || p.name == "z") ||
                        p.type == PlyType::kF32;
               });
      });
  std::vector<double>* coordinates = float_coordinates ? nullptr : &out->xyz;
  const size_t header_lines = lines.number();
  PlyValues values(data.substr(lines.offset()), ascii, swap);
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    std::vector<int> role(e.props.size(), kPlyOther);
    // The header's count is not trusted for memory: every element takes at least a byte.
    const size_t expected = std::min(e.count, data.size());
    if (is_vertex) {
      for (int axis = 0; axis < 3; ++axis) {
        const std::string name(1, char('x' + axis));
        auto it = std::find_if(e.props.begin(), e.props.end(), [&](const PlyProperty& p) {
          return p.name == name && p.count_type == PlyType::kNone;
        });
        if (it == e.props.end())
          return Bad("PLY header: the vertex element has no scalar property '", Excerpt(name), "'");
        role[size_t(it - e.props.begin())] = axis;
      }
      if (coordinates != nullptr) {
        coordinates->reserve(3 * expected);
      } else {
        mesh.positions.reserve(3 * expected);
      }
    }
    if (is_face) {
      mesh.face_fields.clear();
      bool groups = false, corners = false;
      for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        for (size_t j = 0; j < k; ++j)
          if (e.props[j].name == p.name)
            return Bad("PLY header: face property '", Excerpt(p.name), "' is declared twice");
        const bool scalar = p.count_type == PlyType::kNone;
        const bool floating = p.type == PlyType::kF32 || p.type == PlyType::kF64;
        if (!scalar && !corners && (p.name == "vertex_indices" || p.name == "vertex_index")) {
          role[k] = kPlyCorners;
          corners = true;
        } else if (p.name == kPlyGroupProperty) {
          if (!scalar || floating)
            return Bad("PLY header: face property '", kPlyGroupProperty,
                       "' must be a scalar of an integer type (one group id per face)");
          role[k] = kPlyGroup;
          groups = true;
        } else if (scalar && floating && IsPlyFieldName(p.name)) {
          role[k] = int(mesh.face_fields.size());
          mesh.face_fields.push_back({p.name, {}});
        }
      }
      if (!corners && e.count > 0)
        return Bad("PLY header: the face element has no list property 'vertex_indices'");
      if (mesh.face_fields.size() > kMaxFaceFields) {
        std::vector<std::string> names;
        for (const FaceField& f : mesh.face_fields) names.push_back(f.name);
        return Bad("PLY header: ", names.size(), " float face properties (",
                   absl::StrJoin(names, ", "), ") but femsimp carries at most ", kMaxFaceFields,
                   " face fields");
      }
      mesh.triangles.clear();
      mesh.triangles.reserve(3 * expected);
      mesh.face_groups.clear();
      if (groups) mesh.face_groups.reserve(expected);
      for (FaceField& f : mesh.face_fields) f.values.reserve(expected);
    }
    // An element of no property has records of no data, whatever its count (a fuzzed header
    // announced 3e17 of them: walking them read nothing and never ended).
    if (e.props.empty()) continue;
    size_t i = 0;
    if (!ascii && (is_vertex || is_face))
      i = ReadPlyBinaryRecords(e, role, is_vertex, values, mesh, coordinates);
    for (; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        const auto where = [&] { return values.Where(header_lines); };
        const auto fail = [&]() {
          if (values.error())
            return Bad(e.name, " ", i, where(), ": cannot parse '", Excerpt(values.token()),
                       "' as a number");
          return Bad("truncated: header announces ", announced_vertices, " vertices and ",
                     announced_faces, " faces but the data ends in ", e.name, " ", i, where());
        };
        double v;
        if (role[k] >= 0 && is_vertex) {
          double& x = xyz[role[k]];
          if (!values.NextCoordinate(p.type, &x)) return fail();
          if (!FiniteAsFloat(x))
            return Bad("vertex ", i, where(), ": coordinate ", p.name, " = ",
                       values.ascii() ? values.token() : absl::StrCat(x), " is not a finite float");
          continue;
        }
        if (p.count_type == PlyType::kNone) {
          if (!values.Next(p.type, &v)) return fail();
          if (role[k] == kPlyGroup) {
            // ASCII values are not bound by the declared type.
            if (!(v >= 0 && v <= double(std::numeric_limits<uint32_t>::max()) &&
                  v == std::floor(v)))
              return Bad("face ", i, where(), ": group ", v, " is not an integer in [0, 2^32)");
            mesh.face_groups.push_back(uint32_t(v));
          } else if (role[k] >= 0) {
            if (!FiniteAsFloat(v))
              return Bad("face ", i, where(), ": field '", Excerpt(p.name), "' = ", v,
                         " is not a finite float");
            mesh.face_fields[size_t(role[k])].values.push_back(float(v));
          }
          continue;
        }
        double n;
        if (!values.Next(p.count_type, &n)) return fail();
        if (!(n >= 0 && n <= 1e9))  // also keeps the size_t conversion below defined
          return Bad(e.name, " ", i, where(), ": bad list length ", n);
        const bool indices = role[k] == kPlyCorners;
        if (indices && !Readable(int64_t(n))) return Polygon(i, size_t(n), where());
        if (indices) NotePolygon(i, int64_t(n), out);
        for (size_t c = 0; c < size_t(n); ++c) {
          if (!values.Next(p.type, &v)) return fail();
          if (!indices) continue;
          if (v < 0) return Bad("face ", i, where(), " has a negative vertex index ", v);
          if (!(v == std::floor(v) && v <= double(std::numeric_limits<uint32_t>::max())))
            return Bad("face ", i, where(), ": vertex index ", v, " is not a vertex number");
          mesh.triangles.push_back(uint32_t(v));
        }
      }
      if (is_vertex) AppendVertex(xyz, coordinates, mesh);
    }
  }
  if (!HasFaceGroups(mesh)) mesh.face_groups.clear();
  return absl::OkStatus();
}

// After parsing, for the formats whose faces may name vertices the reader has not seen yet (OBJ)
// or whose vertex count the faces do not follow (PLY): every index names a vertex of the file.
absl::Status CheckIndicesInRange(const Reading& parsed) {
  const RawMesh& mesh = parsed.file.mesh;
  const size_t nv = mesh.num_vertices();
  for (size_t c = 0; c < mesh.triangles.size(); ++c) {
    if (mesh.triangles[c] < nv) continue;
    const size_t f = c / 3;
    const size_t line = f < parsed.face_lines.size() ? parsed.face_lines[f] : 0;
    return OutOfRange(f, line ? absl::StrCat(" (line ", line, ")") : "", mesh.triangles[c],
                      int64_t(nv));
  }
  return absl::OkStatus();
}

// Places the part at its local origin (engine/local_origin.h): the double coordinates of the text
// formats and PLY become floats relative to it (ASCII STL's corners are welded then, as floats,
// as binary STL's are); the float coordinates of binary OFF, STL and PLY move there exactly.
void Localize(Reading* parsed) {
  RawMesh& mesh = parsed->file.mesh;
  if (parsed->weld_corners) {
    RawMesh corners;
    StoreRelative(parsed->xyz, &corners);
    Welder welder(&mesh, corners.num_vertices() / 3);
    for (size_t c = 0; c < corners.num_vertices(); ++c) welder.AddCorner(&corners.positions[3 * c]);
    mesh.origin = corners.origin;
  } else if (!parsed->xyz.empty()) {
    StoreRelative(parsed->xyz, &mesh);
  } else {
    MoveToLocalOrigin(&mesh);
  }
  parsed->xyz = {};
}

}  // namespace

absl::StatusOr<ParsedMeshFile> ParseMeshFile(absl::string_view ext, absl::string_view data) {
  Reading parsed;
  absl::Status s;
  if (ext == ".off") {
    s = ParseOff(data, &parsed);
  } else if (ext == ".obj") {
    s = ParseObj(data, &parsed);
  } else if (ext == ".stl") {
    s = ParseStl(data, &parsed);
  } else if (ext == ".ply") {
    s = ParsePly(data, &parsed);
  } else if (ext == ".msh") {
    s = ParseMsh(data, &parsed.file);
  } else {
    s = Bad("no reader for extension '", ext, "'");
  }
  if (s.ok()) Localize(&parsed);
  // Polygons are cut once every position is known (OBJ faces may name later vertices); the cut
  // checks their corners' range itself, by face.
  if (s.ok() && !parsed.polygons.empty()) {
    std::string summary;
    s = TriangulatePolygons(parsed.polygons, &parsed.file.mesh, &parsed.face_lines, &summary);
    if (s.ok()) parsed.file.warnings.push_back(std::move(summary));
  }
  if (s.ok()) s = CheckIndicesInRange(parsed);
  if (!s.ok()) return s;
  return std::move(parsed.file);
}

}  // namespace femsimp
