// gmsh MSH 2.2 and 4.1, ASCII and binary, read in one pass straight into the soup (msh.h). The
// layout is gmsh's reference manual, section "MSH file format" (4.1) and "MSH file format version
// 2 (Legacy)" (2.2).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
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

enum Family : uint8_t {
  kPoint,
  kLine,
  kTriangle,
  kQuadrangle,
  kTetrahedron,
  kHexahedron,
  kPrism,
  kPyramid
};
constexpr uint16_t kFirstOrderNodes[] = {1, 2, 3, 4, 4, 8, 6, 5};
constexpr const char* kPlural[] = {"points",     "lines",     "triangles", "quadrangles",
                                   "tetrahedra", "hexahedra", "prisms",    "pyramids"};
constexpr const char* kSingular[] = {"point",       "line",       "triangle", "quadrangle",
                                     "tetrahedron", "hexahedron", "prism",    "pyramid"};

struct ElementType {
  int type;
  uint16_t nodes;
  Family family;
};

// Every element type of gmsh 4.8 with a fixed node count (gmsh.model.mesh.getElementProperties),
// by type number: a reader must know the node count to step over an element it leaves out.
constexpr ElementType kElementTypes[] = {
    {1, 2, kLine},           {2, 3, kTriangle},       {3, 4, kQuadrangle},
    {4, 4, kTetrahedron},    {5, 8, kHexahedron},     {6, 6, kPrism},
    {7, 5, kPyramid},        {8, 3, kLine},           {9, 6, kTriangle},
    {10, 9, kQuadrangle},    {11, 10, kTetrahedron},  {12, 27, kHexahedron},
    {13, 18, kPrism},        {14, 14, kPyramid},      {15, 1, kPoint},
    {16, 8, kQuadrangle},    {17, 20, kHexahedron},   {18, 15, kPrism},
    {19, 13, kPyramid},      {20, 9, kTriangle},      {21, 10, kTriangle},
    {22, 12, kTriangle},     {23, 15, kTriangle},     {24, 15, kTriangle},
    {25, 21, kTriangle},     {26, 4, kLine},          {27, 5, kLine},
    {28, 6, kLine},          {29, 20, kTetrahedron},  {30, 35, kTetrahedron},
    {31, 56, kTetrahedron},  {32, 22, kTetrahedron},  {33, 28, kTetrahedron},
    {36, 16, kQuadrangle},   {37, 25, kQuadrangle},   {38, 36, kQuadrangle},
    {39, 12, kQuadrangle},   {40, 16, kQuadrangle},   {41, 20, kQuadrangle},
    {42, 28, kTriangle},     {43, 36, kTriangle},     {44, 45, kTriangle},
    {45, 55, kTriangle},     {46, 66, kTriangle},     {47, 49, kQuadrangle},
    {48, 64, kQuadrangle},   {49, 81, kQuadrangle},   {50, 100, kQuadrangle},
    {51, 121, kQuadrangle},  {52, 18, kTriangle},     {53, 21, kTriangle},
    {54, 24, kTriangle},     {55, 27, kTriangle},     {56, 30, kTriangle},
    {57, 24, kQuadrangle},   {58, 28, kQuadrangle},   {59, 32, kQuadrangle},
    {60, 36, kQuadrangle},   {61, 40, kQuadrangle},   {62, 7, kLine},
    {63, 8, kLine},          {64, 9, kLine},          {65, 10, kLine},
    {66, 11, kLine},         {71, 84, kTetrahedron},  {72, 120, kTetrahedron},
    {73, 165, kTetrahedron}, {74, 220, kTetrahedron}, {75, 286, kTetrahedron},
    {79, 34, kTetrahedron},  {80, 40, kTetrahedron},  {81, 46, kTetrahedron},
    {82, 52, kTetrahedron},  {83, 58, kTetrahedron},  {84, 1, kLine},
    {85, 1, kTriangle},      {86, 1, kQuadrangle},    {87, 1, kTetrahedron},
    {88, 1, kHexahedron},    {89, 1, kPrism},         {92, 64, kHexahedron},
    {93, 125, kHexahedron},  {94, 216, kHexahedron},  {95, 343, kHexahedron},
    {96, 512, kHexahedron},  {97, 729, kHexahedron},  {98, 1000, kHexahedron},
    {99, 32, kHexahedron},   {100, 44, kHexahedron},  {101, 56, kHexahedron},
    {102, 68, kHexahedron},  {103, 80, kHexahedron},  {104, 92, kHexahedron},
    {105, 104, kHexahedron}, {118, 30, kPyramid},     {119, 55, kPyramid},
    {120, 91, kPyramid},     {121, 140, kPyramid},    {122, 204, kPyramid},
    {123, 285, kPyramid},    {124, 385, kPyramid},    {125, 21, kPyramid},
    {126, 29, kPyramid},     {127, 37, kPyramid},     {128, 45, kPyramid},
    {129, 53, kPyramid},     {130, 61, kPyramid},     {131, 69, kPyramid},
    {132, 1, kPyramid},      {137, 16, kTetrahedron}};

constexpr int kTriangleType = 2, kQuadrangleType = 3;  // first order: 3 and 4 nodes

const ElementType* FindType(int64_t type) {
  const auto it = std::lower_bound(std::begin(kElementTypes), std::end(kElementTypes), type,
                                   [](const ElementType& e, int64_t t) { return e.type < t; });
  return it != std::end(kElementTypes) && it->type == type ? it : nullptr;
}

// "1234 tetrahedra", "1 line", "56 10-node tetrahedra".
std::string CountOf(uint64_t n, const ElementType& t) {
  const char* name = (n == 1 ? kSingular : kPlural)[t.family];
  if (t.nodes == kFirstOrderNodes[t.family]) return absl::StrCat(n, " ", name);
  return absl::StrCat(n, " ", t.nodes, "-node ", name);
}

// Int, Size and Double are the format's int, size_t and double: binary in the binary parts of a
// binary file, tokens otherwise.
enum class Kind { kInt, kSize };

class MshReader {
 public:
  MshReader(absl::string_view data, ParsedMeshFile* out) : data_(data), out_(out) {}

  absl::Status Read() {
    if (absl::Status s = ReadFormat(); !s.ok()) return s;
    while (true) {
      SkipSpace();
      if (pos_ >= data_.size()) break;
      const size_t at = pos_;
      absl::string_view header = RestOfLine();
      header = absl::StripTrailingAsciiWhitespace(header);
      if (header.empty() || header[0] != '$' || absl::StartsWith(header, "$End"))
        return Bad("expected a section ('$Name')", Where(at), ", found '", Excerpt(header), "'");
      section_ = std::string(header);
      absl::Status s;
      if (header == "$PhysicalNames") {
        s = ReadPhysicalNames();
      } else if (header == "$Entities" || header == "$PartitionedEntities") {
        s = v4_ ? ReadEntities(header == "$PartitionedEntities") : SkipSection();
      } else if (header == "$Nodes") {
        s = v4_ ? ReadNodes4() : ReadNodes2();
      } else if (header == "$Elements") {
        s = v4_ ? ReadElements4() : ReadElements2();
      } else {
        if (header == "$NodeData" || header == "$ElementData" || header == "$ElementNodeData")
          ++data_sections_[section_];
        s = SkipSection();
      }
      if (!s.ok()) return s;
    }
    return Finish();
  }

 private:
  // ------------------------------------------------------------------------- positions
  // Where the value at or after `at` starts.
  std::string Where(size_t at) const {
    if (binary_) return absl::StrCat(" (byte ", at, ")");
    while (at < data_.size() && absl::ascii_isspace(data_[at])) ++at;
    return absl::StrCat(" (line ", 1 + std::count(data_.begin(), data_.begin() + at, '\n'), ")");
  }
  absl::Status Truncated() const {
    return Bad("truncated: the file ends inside ", section_, Where(data_.size()));
  }

  // ------------------------------------------------------------------------- text
  void SkipSpace() {
    while (pos_ < data_.size() && absl::ascii_isspace(data_[pos_])) ++pos_;
  }
  // The rest of the current line (without its '\n'); moves past it.
  absl::string_view RestOfLine() {
    size_t end = data_.find('\n', pos_);
    if (end == absl::string_view::npos) end = data_.size();
    absl::string_view line = data_.substr(pos_, end - pos_);
    pos_ = std::min(end + 1, data_.size());
    return line;
  }
  bool Token(absl::string_view* t) {
    SkipSpace();
    if (pos_ >= data_.size()) return false;
    size_t end = pos_;
    while (end < data_.size() && !absl::ascii_isspace(data_[end])) ++end;
    *t = data_.substr(pos_, end - pos_);
    pos_ = end;
    return true;
  }
  // An integer written as text in every file (counts of 2.2, $PhysicalNames).
  absl::Status TextInt(absl::string_view what, int64_t* v) {
    absl::string_view t;
    if (!Token(&t)) return Truncated();
    if (!ParseInt(t, v))
      return Bad(section_, Where(pos_ - t.size()), ": cannot parse '", Excerpt(t), "' as ", what);
    return absl::OkStatus();
  }

  // ------------------------------------------------------------------------- values
  bool Need(size_t bytes) const { return bytes <= data_.size() - pos_; }

  // An int (4 bytes) or size_t (data-size bytes) in binary, an integer token in ASCII. Sizes are
  // never negative.
  absl::Status Integer(Kind kind, absl::string_view what, int64_t* v) {
    if (!binary_) {
      if (absl::Status s = TextInt(what, v); !s.ok()) return s;
      if (kind == Kind::kSize && *v < 0)
        return Bad(section_, Where(last_token_start()), ": ", what, " ", *v, " is negative");
      return absl::OkStatus();
    }
    const size_t bytes = kind == Kind::kInt ? 4 : size_bytes_;
    if (!Need(bytes)) return Truncated();
    if (bytes == 4) {
      *v = kind == Kind::kInt ? int64_t(LoadBytes<int32_t>(data_.data() + pos_, swap_))
                              : int64_t(LoadBytes<uint32_t>(data_.data() + pos_, swap_));
    } else {
      const uint64_t u = LoadBytes<uint64_t>(data_.data() + pos_, swap_);
      if (u > uint64_t(std::numeric_limits<int64_t>::max()))
        return Bad(section_, Where(pos_), ": ", what, " ", u, " is out of range");
      *v = int64_t(u);
    }
    pos_ += bytes;
    return absl::OkStatus();
  }
  size_t last_token_start() const {
    size_t p = pos_;
    while (p > 0 && !absl::ascii_isspace(data_[p - 1])) --p;
    return p;
  }
  // A count of things that follow, each taking at least one byte: bounded by the file's size.
  absl::Status Count(Kind kind, absl::string_view what, size_t* n) {
    int64_t v = 0;
    const size_t at = pos_;
    if (absl::Status s = Integer(kind, what, &v); !s.ok()) return s;
    if (v < 0 || uint64_t(v) > data_.size())
      return Bad(section_, Where(at), ": ", what, " ", v, " does not fit the file (", data_.size(),
                 " bytes)");
    *n = size_t(v);
    return absl::OkStatus();
  }
  absl::Status Double(absl::string_view what, double* v) {
    if (binary_) {
      if (!Need(8)) return Truncated();
      *v = LoadBytes<double>(data_.data() + pos_, swap_);
      pos_ += 8;
      return absl::OkStatus();
    }
    absl::string_view t;
    if (!Token(&t)) return Truncated();
    if (!ParseDouble(t, v))
      return Bad(section_, Where(pos_ - t.size()), ": cannot parse '", Excerpt(t), "' as ", what);
    return absl::OkStatus();
  }
  // A coordinate of node `tag`, in double until the part is placed at its local origin.
  absl::Status Coordinate(int64_t tag, double* x) {
    const size_t at = pos_;
    if (binary_) {
      if (absl::Status s = Double("a coordinate", x); !s.ok()) return s;
      if (!FiniteAsFloat(*x))
        return Bad("node ", tag, Where(at), ": coordinate ", *x, " is not a finite float");
      return absl::OkStatus();
    }
    absl::string_view t;
    if (!Token(&t)) return Truncated();
    if (!ParseCoordinate(t, x))
      return Bad("node ", tag, Where(pos_ - t.size()), ": cannot parse '", Excerpt(t),
                 "' as a coordinate");
    if (!FiniteAsFloat(*x))
      return Bad("node ", tag, Where(pos_ - t.size()), ": coordinate '", Excerpt(t),
                 "' is not a finite float");
    return absl::OkStatus();
  }
  // Steps over `bytes` of binary data.
  absl::Status Skip(size_t bytes) {
    if (!Need(bytes)) return Truncated();
    pos_ += bytes;
    return absl::OkStatus();
  }

  // The "$EndName" line closing the current section.
  absl::Status End() {
    // A binary section's data ends with a newline before its end marker.
    SkipSpace();
    const size_t at = pos_;
    const std::string end = absl::StrCat("$End", section_.substr(1));
    absl::string_view line = absl::StripTrailingAsciiWhitespace(RestOfLine());
    if (line == end) return absl::OkStatus();
    if (at >= data_.size()) return Truncated();
    return Bad("expected '", end, "'", Where(at), ", found '", Excerpt(line), "'");
  }
  absl::Status SkipSection() {
    const std::string end = absl::StrCat("$End", section_.substr(1));
    // Binary data may hold the bytes of the marker; gmsh skips to it the same way.
    const size_t at = data_.find(end, pos_);
    if (at == absl::string_view::npos)
      return Bad("truncated: ", section_, " without '", end, "'", Where(data_.size()));
    pos_ = at;
    return End();
  }

  // ------------------------------------------------------------------------- sections
  absl::Status ReadFormat() {
    SkipSpace();
    const size_t at = pos_;
    absl::string_view line = absl::StripTrailingAsciiWhitespace(RestOfLine());
    if (line == "$NOD" || line == "$NOE")
      return Bad("MSH version 1 is not supported (2.2 and 4.1 are): save the mesh as 4.1");
    if (line != "$MeshFormat")
      return Bad("not a gmsh MSH file: expected '$MeshFormat'", Where(at), ", found '",
                 Excerpt(line), "'");
    section_ = "$MeshFormat";
    const size_t version_at = pos_;
    std::vector<absl::string_view> tok = absl::StrSplit(absl::StripAsciiWhitespace(RestOfLine()),
                                                        absl::ByAnyChar(" \t"), absl::SkipEmpty());
    if (tok.size() < 3)
      return Bad("$MeshFormat", Where(version_at),
                 ": expected 'version file-type data-size', found ", tok.size(), " values");
    const absl::string_view version = tok[0];
    if (version == "4.1") {
      v4_ = true;
    } else if (version == "2.2" || version == "2" || version == "2.0" || version == "2.1") {
      v4_ = false;
    } else if (version == "4" || version == "4.0") {
      return Bad("MSH version ", version,
                 " is not supported (2.2 and 4.1 are): save the mesh as 4.1 (gmsh -format msh41)");
    } else {
      return Bad("unknown MSH version '", Excerpt(version), "'", Where(version_at),
                 ": femsimp reads 2.2 and 4.1");
    }
    if (tok[1] != "0" && tok[1] != "1")
      return Bad("$MeshFormat", Where(version_at), ": file-type '", Excerpt(tok[1]),
                 "' is neither 0 (ASCII) nor 1 (binary)");
    binary_ = tok[1] == "1";
    if (tok[2] == "8") {
      size_bytes_ = 8;
    } else if (tok[2] == "4" && v4_) {
      size_bytes_ = 4;
    } else {
      return Bad("$MeshFormat", Where(version_at), ": data-size '", Excerpt(tok[2]), "' is not ",
                 v4_ ? "4 or 8" : "8");
    }
    if (binary_) {
      // The int 1 in the writer's byte order.
      if (!Need(4)) return Truncated();
      const char* p = data_.data() + pos_;
      if (LoadBytes<int32_t>(p, false) == 1) {
        swap_ = false;
      } else if (LoadBytes<int32_t>(p, true) == 1) {
        swap_ = true;  // written on a host of the other byte order: every value is swapped
      } else {
        return Bad("$MeshFormat", Where(pos_),
                   ": binary file without the int 1 that gives its byte order");
      }
      pos_ += 4;
    }
    return End();
  }

  absl::Status ReadPhysicalNames() {
    int64_t n;
    if (absl::Status s = TextInt("a name count", &n); !s.ok()) return s;
    for (int64_t i = 0; i < n; ++i) {
      int64_t dim, tag;
      if (absl::Status s = TextInt("a dimension", &dim); !s.ok()) return s;
      const size_t tag_at = pos_;
      if (absl::Status s = TextInt("a physical tag", &tag); !s.ok()) return s;
      SkipSpace();
      const size_t at = pos_;
      const size_t eol = std::min(data_.find('\n', pos_), data_.size());
      const size_t close = at < eol ? data_.find('"', at + 1) : absl::string_view::npos;
      if (at >= data_.size()) return Truncated();
      if (data_[at] != '"' || close == absl::string_view::npos || close >= eol)
        return Bad("$PhysicalNames", Where(at), ": expected a name in double quotes");
      pos_ = close + 1;
      if (dim != 2) continue;
      if (tag <= 0 || tag > int64_t{std::numeric_limits<uint32_t>::max()})
        return Bad("$PhysicalNames", Where(tag_at), ": physical tag ", tag,
                   " is not a group id in [1, 2^32)");
      out_->group_names.try_emplace(uint32_t(tag), data_.substr(at + 1, close - at - 1));
    }
    return End();
  }

  // Physical tags of every entity; the surfaces' first one is their triangles' group. A
  // partitioned mesh's elements are on its partition entities ($PartitionedEntities, which
  // follows $Entities): they replace the model's.
  absl::Status ReadEntities(bool partitioned) {
    int64_t ignored;
    if (partitioned) {
      surface_group_.clear();
      surfaces_in_several_groups_ = 0;
      size_t ghosts;
      if (absl::Status s = Count(Kind::kSize, "a partition count", &ghosts); !s.ok()) return s;
      if (absl::Status s = Count(Kind::kSize, "a ghost entity count", &ghosts); !s.ok()) return s;
      for (size_t k = 0; k < 2 * ghosts; ++k)  // ghost entity tag, partition
        if (absl::Status s = Integer(Kind::kInt, "a ghost entity", &ignored); !s.ok()) return s;
    }
    size_t count[4];
    for (size_t& c : count)
      if (absl::Status s = Count(Kind::kSize, "an entity count", &c); !s.ok()) return s;
    for (int dim = 0; dim < 4; ++dim) {
      for (size_t i = 0; i < count[dim]; ++i) {
        int64_t tag, phys;
        if (absl::Status s = Integer(Kind::kInt, "an entity tag", &tag); !s.ok()) return s;
        size_t n;
        if (partitioned) {  // parent dimension and tag, the partitions
          for (int k = 0; k < 2; ++k)
            if (absl::Status s = Integer(Kind::kInt, "a parent entity", &ignored); !s.ok())
              return s;
          if (absl::Status s = Count(Kind::kSize, "a partition count", &n); !s.ok()) return s;
          for (size_t k = 0; k < n; ++k)
            if (absl::Status s = Integer(Kind::kInt, "a partition", &ignored); !s.ok()) return s;
        }
        double box;
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k)
          if (absl::Status s = Double("a coordinate", &box); !s.ok()) return s;
        if (absl::Status s = Count(Kind::kSize, "a physical tag count", &n); !s.ok()) return s;
        for (size_t k = 0; k < n; ++k) {
          const size_t at = pos_;
          if (absl::Status s = Integer(Kind::kInt, "a physical tag", &phys); !s.ok()) return s;
          if (dim != 2) continue;
          // 0 is femsimp's own "no group" in a file with groups (msh_writer.cc).
          if (phys < 0 || phys > int64_t{std::numeric_limits<uint32_t>::max()})
            return Bad(section_, Where(at), ": surface ", tag, " has physical tag ", phys,
                       ", not a group id in [0, 2^32)");
          if (k == 0) surface_group_[tag] = uint32_t(phys);
          if (k == 1) ++surfaces_in_several_groups_;
        }
        if (dim == 0) continue;
        if (absl::Status s = Count(Kind::kSize, "a bounding entity count", &n); !s.ok()) return s;
        for (size_t k = 0; k < n; ++k)
          if (absl::Status s = Integer(Kind::kInt, "a bounding entity", &phys); !s.ok()) return s;
      }
    }
    return End();
  }

  // The header's count is not trusted for memory: a node takes at least 8 bytes of the file.
  void ReserveNodes(size_t count) {
    nodes_.reserve(nodes_.size() + 3 * std::min(count, data_.size() / 8));
  }

  absl::Status AddNode(int64_t tag, size_t at, const double xyz[3]) {
    if (tag <= 0) return Bad("$Nodes", Where(at), ": node tag ", tag, " is not positive");
    if (!node_index_.try_emplace(tag, uint32_t(nodes_.size() / 3)).second)
      return Bad("$Nodes", Where(at), ": node ", tag, " is defined twice");
    if (nodes_.size() / 3 >= std::numeric_limits<uint32_t>::max())
      return Bad("$Nodes", Where(at), ": more than 2^32 nodes");
    nodes_.insert(nodes_.end(), xyz, xyz + 3);
    return absl::OkStatus();
  }

  absl::Status ReadNodes4() {
    size_t blocks = 0, total = 0;
    int64_t ignored;
    if (absl::Status s = Count(Kind::kSize, "a block count", &blocks); !s.ok()) return s;
    if (absl::Status s = Count(Kind::kSize, "a node count", &total); !s.ok()) return s;
    for (int k = 0; k < 2; ++k)  // the lowest and highest tag
      if (absl::Status s = Integer(Kind::kSize, "a node tag", &ignored); !s.ok()) return s;
    ReserveNodes(total);
    std::vector<std::pair<int64_t, size_t>> tags;
    for (size_t b = 0; b < blocks; ++b) {
      int64_t dim, parametric;
      size_t n;
      const size_t at = pos_;
      if (absl::Status s = Integer(Kind::kInt, "an entity dimension", &dim); !s.ok()) return s;
      if (absl::Status s = Integer(Kind::kInt, "an entity tag", &ignored); !s.ok()) return s;
      if (absl::Status s = Integer(Kind::kInt, "'parametric'", &parametric); !s.ok()) return s;
      if (absl::Status s = Count(Kind::kSize, "a node count", &n); !s.ok()) return s;
      if (dim < 0 || dim > 3 || (parametric != 0 && parametric != 1))
        return Bad("$Nodes", Where(at), ": block ", b, " has entity dimension ", dim,
                   " and parametric ", parametric, " (expected 0..3 and 0 or 1)");
      tags.clear();
      for (size_t i = 0; i < n; ++i) {
        const size_t tag_at = pos_;
        int64_t tag;
        if (absl::Status s = Integer(Kind::kSize, "a node tag", &tag); !s.ok()) return s;
        tags.emplace_back(tag, tag_at);
      }
      // x y z, then u (curves and up), v (surfaces and up), w (volumes) of parametric nodes.
      const size_t extra = parametric ? size_t(dim) : 0;
      for (const auto& [tag, tag_at] : tags) {
        double xyz[3];
        for (double& x : xyz)
          if (absl::Status s = Coordinate(tag, &x); !s.ok()) return s;
        double uvw;
        for (size_t k = 0; k < extra; ++k)
          if (absl::Status s = Double("a parametric coordinate", &uvw); !s.ok()) return s;
        if (absl::Status s = AddNode(tag, tag_at, xyz); !s.ok()) return s;
      }
    }
    return End();
  }

  absl::Status ReadNodes2() {
    size_t n;
    int64_t count;
    const size_t at = pos_;
    if (absl::Status s = TextInt("a node count", &count); !s.ok()) return s;
    if (count < 0 || uint64_t(count) > data_.size())
      return Bad("$Nodes", Where(at), ": node count ", count, " does not fit the file");
    n = size_t(count);
    if (binary_ && pos_ < data_.size() && data_[pos_] == '\r') ++pos_;
    if (binary_ && pos_ < data_.size() && data_[pos_] == '\n') ++pos_;
    ReserveNodes(n);
    for (size_t i = 0; i < n; ++i) {
      const size_t tag_at = pos_;
      int64_t tag;
      if (absl::Status s = Integer(Kind::kInt, "a node tag", &tag); !s.ok()) return s;
      double xyz[3];
      for (double& x : xyz)
        if (absl::Status s = Coordinate(tag, &x); !s.ok()) return s;
      if (absl::Status s = AddNode(tag, tag_at, xyz); !s.ok()) return s;
    }
    return End();
  }

  // The element's nodes (after its tag), as a face when it is a triangle.
  absl::Status ReadElementNodes(const ElementType& type, int64_t element, size_t at,
                                uint32_t group) {
    const bool quadrangle = type.type == kQuadrangleType;
    if (type.type != kTriangleType && !quadrangle) {
      ++left_out_[type.type];
      if (binary_) return Skip(type.nodes * (v4_ ? size_bytes_ : 4));
      absl::string_view t;
      for (size_t k = 0; k < type.nodes; ++k)
        if (!Token(&t)) return Truncated();
      return absl::OkStatus();
    }
    // A quadrangle is cut into two triangles once the nodes are numbered (polygons.h).
    if (quadrangle) polygons_.push_back({groups_.size(), 4});
    for (int k = 0; k < type.nodes; ++k) {
      int64_t tag;
      if (absl::Status s = Integer(v4_ ? Kind::kSize : Kind::kInt, "a node tag", &tag); !s.ok())
        return s;
      const auto it = node_index_.find(tag);
      if (it == node_index_.end())
        return Bad("element ", element, Where(at), " references node ", tag,
                   ", which $Nodes does not define");
      triangles_.push_back(it->second);
    }
    groups_.push_back(group);
    return absl::OkStatus();
  }

  absl::StatusOr<const ElementType*> Type(int64_t type, size_t at) {
    const ElementType* t = FindType(type);
    if (t == nullptr)
      return Bad("$Elements", Where(at), ": element type ", type,
                 " is not a gmsh element type with a fixed node count");
    return t;
  }

  absl::Status ReadElements4() {
    size_t blocks = 0, total = 0;
    int64_t ignored;
    if (absl::Status s = Count(Kind::kSize, "a block count", &blocks); !s.ok()) return s;
    if (absl::Status s = Count(Kind::kSize, "an element count", &total); !s.ok()) return s;
    for (int k = 0; k < 2; ++k)
      if (absl::Status s = Integer(Kind::kSize, "an element tag", &ignored); !s.ok()) return s;
    for (size_t b = 0; b < blocks; ++b) {
      int64_t dim, entity, type_number;
      size_t n;
      if (absl::Status s = Integer(Kind::kInt, "an entity dimension", &dim); !s.ok()) return s;
      if (absl::Status s = Integer(Kind::kInt, "an entity tag", &entity); !s.ok()) return s;
      const size_t type_at = pos_;
      if (absl::Status s = Integer(Kind::kInt, "an element type", &type_number); !s.ok()) return s;
      if (absl::Status s = Count(Kind::kSize, "an element count", &n); !s.ok()) return s;
      absl::StatusOr<const ElementType*> type = Type(type_number, type_at);
      if (!type.ok()) return type.status();
      uint32_t group = 0;
      if (const auto it = surface_group_.find(entity); dim == 2 && it != surface_group_.end())
        group = it->second;
      for (size_t i = 0; i < n; ++i) {
        const size_t at = pos_;
        int64_t element;
        if (absl::Status s = Integer(Kind::kSize, "an element tag", &element); !s.ok()) return s;
        if (absl::Status s = ReadElementNodes(**type, element, at, group); !s.ok()) return s;
      }
    }
    return End();
  }

  // 2.2: an element's group is its first tag (the physical group; 0: none).
  absl::Status Group2(int64_t tags, size_t at, uint32_t* group) {
    *group = 0;
    for (int64_t k = 0; k < tags; ++k) {
      int64_t tag;
      if (absl::Status s = Integer(Kind::kInt, "an element tag", &tag); !s.ok()) return s;
      if (k > 0) continue;
      if (tag < 0 || tag > int64_t{std::numeric_limits<uint32_t>::max()})
        return Bad("$Elements", Where(at), ": physical tag ", tag,
                   " is not a group id in [0, 2^32)");
      *group = uint32_t(tag);
    }
    return absl::OkStatus();
  }

  absl::Status ReadElements2() {
    int64_t count;
    const size_t count_at = pos_;
    if (absl::Status s = TextInt("an element count", &count); !s.ok()) return s;
    if (count < 0 || uint64_t(count) > data_.size())
      return Bad("$Elements", Where(count_at), ": element count ", count, " does not fit the file");
    if (binary_ && pos_ < data_.size() && data_[pos_] == '\r') ++pos_;
    if (binary_ && pos_ < data_.size() && data_[pos_] == '\n') ++pos_;
    int64_t read = 0;
    while (read < count) {
      // ASCII: every element has its header; binary: a header per run of elements.
      int64_t element = 0, type_number, following = 1, tags;
      const size_t at = pos_;
      if (!binary_)
        if (absl::Status s = Integer(Kind::kInt, "an element tag", &element); !s.ok()) return s;
      const size_t type_at = pos_;
      if (absl::Status s = Integer(Kind::kInt, "an element type", &type_number); !s.ok()) return s;
      if (binary_)
        if (absl::Status s = Integer(Kind::kInt, "an element count", &following); !s.ok()) return s;
      if (absl::Status s = Integer(Kind::kInt, "a tag count", &tags); !s.ok()) return s;
      absl::StatusOr<const ElementType*> type = Type(type_number, type_at);
      if (!type.ok()) return type.status();
      if (following < 1 || following > count - read || tags < 0 || uint64_t(tags) > data_.size())
        return Bad("$Elements", Where(at), ": bad element header (", following, " elements with ",
                   tags, " tags each; ", count - read, " elements remain)");
      for (int64_t i = 0; i < following; ++i) {
        const size_t element_at = binary_ ? pos_ : at;
        if (binary_)
          if (absl::Status s = Integer(Kind::kInt, "an element tag", &element); !s.ok()) return s;
        uint32_t group;
        if (absl::Status s = Group2(tags, element_at, &group); !s.ok()) return s;
        if (absl::Status s = ReadElementNodes(**type, element, element_at, group); !s.ok())
          return s;
      }
      read += following;
    }
    return End();
  }

  // ------------------------------------------------------------------------- the soup
  absl::Status Finish() {
    std::vector<std::pair<int, uint64_t>> left(left_out_.begin(), left_out_.end());
    std::stable_sort(left.begin(), left.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<std::string> parts;
    for (const auto& [type, n] : left) parts.push_back(CountOf(n, *FindType(type)));
    if (triangles_.empty() && !parts.empty())
      return Bad(
          "no 3-node triangles or 4-node quadrangles (element types 2 and 3) in the file, "
          "only ",
          absl::StrJoin(parts, ", "),
          ": femsimp simplifies surface meshes (save the boundary's triangles)");

    // Only the nodes of triangles, in file order.
    std::vector<uint32_t> index(nodes_.size() / 3, ~0u);
    RawMesh& mesh = out_->mesh;
    for (uint32_t v : triangles_) index[v] = 0;
    std::vector<double> used;
    for (size_t v = 0; v < index.size(); ++v) {
      if (index[v] != 0) continue;
      index[v] = uint32_t(used.size() / 3);
      used.insert(used.end(), &nodes_[3 * v], &nodes_[3 * v + 3]);
    }
    StoreRelative(used, &mesh);
    const size_t unused = index.size() - mesh.num_vertices();
    mesh.triangles.reserve(triangles_.size());
    for (uint32_t v : triangles_) mesh.triangles.push_back(index[v]);
    mesh.face_groups = std::move(groups_);
    if (!polygons_.empty()) {
      std::string summary;
      if (absl::Status s = TriangulatePolygons(polygons_, &mesh, nullptr, &summary); !s.ok())
        return s;
      out_->warnings.push_back("msh: " + summary);
    }
    if (!HasFaceGroups(mesh)) mesh.face_groups.clear();

    if (unused > 0)
      parts.push_back(absl::StrCat(unused, unused == 1 ? " node" : " nodes", " no triangle uses"));
    if (!parts.empty())
      out_->warnings.push_back(absl::StrCat("msh: left out ", absl::StrJoin(parts, ", ")));
    if (!data_sections_.empty()) {
      std::vector<std::string> data;
      for (const auto& [name, n] : data_sections_) data.push_back(absl::StrCat(n, " ", name));
      out_->warnings.push_back(absl::StrCat("msh: left out ", absl::StrJoin(data, ", "),
                                            " (femsimp reads no fields from MSH files)"));
    }
    if (surfaces_in_several_groups_ > 0)
      out_->warnings.push_back(absl::StrCat(
          "msh: ", surfaces_in_several_groups_,
          " surfaces are in several physical groups: their triangles are in the first one's"));
    return absl::OkStatus();
  }

  absl::string_view data_;
  ParsedMeshFile* out_;
  size_t pos_ = 0;
  std::string section_;
  bool v4_ = false, binary_ = false, swap_ = false;
  size_t size_bytes_ = 8;
  absl::flat_hash_map<int64_t, uint32_t> node_index_;  // node tag -> index in nodes_
  absl::flat_hash_map<int64_t, uint32_t> surface_group_;
  size_t surfaces_in_several_groups_ = 0;
  std::vector<double> nodes_;
  std::vector<uint32_t> triangles_, groups_;  // the corners of every face, and its group
  std::vector<PolygonFace> polygons_;         // the faces of four corners
  std::map<int, uint64_t> left_out_;          // element type -> count
  std::map<std::string, uint64_t> data_sections_;
};

}  // namespace

absl::Status ParseMsh(absl::string_view data, ParsedMeshFile* out) {
  return MshReader(data, out).Read();
}

}  // namespace femsimp
