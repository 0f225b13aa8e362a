#include "engine/io/face_data.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <system_error>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/strip.h"
#include "engine/io/msh.h"
#include "engine/local_origin.h"

namespace femsimp {
namespace {

// "group_<n>" with n in canonical decimal, so that id -> name -> id is exact both ways.
bool CanonicalGroupId(absl::string_view name, uint32_t* id) {
  if (!absl::ConsumePrefix(&name, "group_") || name.empty() || name.size() > 10) return false;
  if (name.size() > 1 && name[0] == '0') return false;
  uint64_t v = 0;
  for (char c : name) {
    if (!absl::ascii_isdigit(c)) return false;
    v = 10 * v + uint64_t(c - '0');
  }
  if (v > std::numeric_limits<uint32_t>::max()) return false;
  *id = uint32_t(v);
  return true;
}

const char* FormatName(absl::string_view ext) {
  if (ext == ".obj") return "OBJ";
  if (ext == ".ply") return "PLY";
  if (ext == ".off") return "OFF";
  if (ext == ".stl") return "STL";
  if (ext == ".msh") return "MSH";
  return "these";
}

bool HoldsGroups(absl::string_view ext) {
  return ext == ".obj" || ext == ".ply" || ext == ".msh" || ext == ".stl";
}
bool HoldsFields(absl::string_view ext) { return ext == ".ply"; }

std::vector<std::string> FieldNames(const RawMesh& mesh) {
  std::vector<std::string> names;
  for (const FaceField& f : mesh.face_fields) names.push_back(f.name);
  return names;
}

template <typename T>
std::array<char, sizeof(T)> LittleEndianBytes(T v) {
  auto bytes = std::bit_cast<std::array<char, sizeof(T)>>(v);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  return bytes;
}

template <typename T>
void AppendLittleEndian(std::string* s, T v) {
  const auto bytes = LittleEndianBytes(v);
  s->append(bytes.data(), bytes.size());
}

// Writes v at *out and moves *out past it (into a buffer sized beforehand).
template <typename T>
void PutLittleEndian(char** out, T v) {
  const auto bytes = LittleEndianBytes(v);
  std::memcpy(*out, bytes.data(), bytes.size());
  *out += bytes.size();
}

}  // namespace

void AppendFloat(std::string* s, float v) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  s->append(buf, ec == std::errc() ? end : buf);
}

void AppendCoordinate(std::string* s, double origin, float position) {
  if (origin == 0.0) return AppendFloat(s, position);
  // The fewest digits that read back (as femsimp's readers read: in double, minus the origin, to
  // float) to this position: a vertex that did not move is written as its file wrote it.
  const double at = origin + double(position);
  char buf[32];
  const auto text = [&](int digits) {
    return std::to_chars(buf, buf + sizeof(buf), at, std::chars_format::general, digits).ptr;
  };
  const auto reads_back = [&](int digits) {
    double x = 0.0;
    std::from_chars(buf, text(digits), x);
    return static_cast<float>(x - origin) == position;
  };
  int lo = 1, hi = 17;  // 17 digits: `at` itself
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (reads_back(mid)) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  s->append(buf, text(lo));
}

std::string ObjGroupName(uint32_t id, const GroupNames& names) {
  if (auto it = names.find(id); it != names.end()) return it->second;
  return id == 0 ? kObjDefaultGroup : absl::StrCat("group_", id);
}

std::vector<uint32_t> ObjGroupIds(const std::vector<std::string>& distinct_names,
                                  GroupNames* names) {
  std::vector<uint32_t> ids(distinct_names.size());
  std::vector<bool> fixed(distinct_names.size(), false);
  std::set<uint32_t> taken;
  for (size_t i = 0; i < distinct_names.size(); ++i) {
    if (distinct_names[i] == kObjDefaultGroup) {
      ids[i] = 0;
      fixed[i] = true;
    } else {
      fixed[i] = CanonicalGroupId(distinct_names[i], &ids[i]);
    }
    if (fixed[i]) taken.insert(ids[i]);
  }
  uint32_t next = 1;
  for (size_t i = 0; i < distinct_names.size(); ++i) {
    if (fixed[i]) continue;
    while (taken.count(next)) ++next;
    ids[i] = next;
    taken.insert(next);
    (*names)[next] = distinct_names[i];
  }
  return ids;
}

bool IsPlyFieldName(absl::string_view name) {
  static const absl::string_view kNotFields[] = {
      kPlyGroupProperty, "vertex_indices", "vertex_index", "nx", "ny", "nz", "red",
      "green",           "blue",           "alpha"};
  return std::find(std::begin(kNotFields), std::end(kNotFields), name) == std::end(kNotFields);
}

bool HasFaceGroups(const RawMesh& mesh) {
  return std::any_of(mesh.face_groups.begin(), mesh.face_groups.end(),
                     [](uint32_t g) { return g != 0; });
}

absl::Status CheckFormatHolds(absl::string_view ext, const RawMesh& mesh) {
  const bool lost_groups = HasFaceGroups(mesh) && !HoldsGroups(ext);
  const bool lost_fields = !mesh.face_fields.empty() && !HoldsFields(ext);
  if (!lost_groups && !lost_fields) return absl::OkStatus();
  std::string what;
  if (lost_groups) what = "face groups";
  if (lost_fields)
    absl::StrAppend(&what, lost_groups ? " and " : "", "face fields (",
                    absl::StrJoin(FieldNames(mesh), ", "), ")");
  return absl::InvalidArgumentError(
      absl::StrCat(FormatName(ext), " files cannot hold ", what, "; write ",
                   lost_fields ? ".ply to keep them" : ".obj, .ply, .msh or .stl to keep them"));
}

void DropUnheldFaceData(absl::string_view ext, RawMesh* mesh) {
  if (!HoldsGroups(ext)) mesh->face_groups.clear();
  if (!HoldsFields(ext)) mesh->face_fields.clear();
}

absl::Status CheckFaceData(absl::string_view ext, const RawMesh& mesh, const GroupNames& names) {
  if (ext == ".obj" && !mesh.face_groups.empty()) {
    for (const auto& [id, name] : names)
      if (name.empty() || name.find_first_of("\r\n") != std::string::npos)
        return absl::InvalidArgumentError(absl::StrCat(
            "group ", id, ": name '", name, "' cannot be an OBJ group name (empty or multi-line)"));
  }
  if (ext == ".stl" && HasFaceGroups(mesh)) {
    // Read back as the rest of the `solid` line, blanks at its ends stripped.
    for (const auto& [id, name] : names)
      if (name.empty() || name != absl::StripAsciiWhitespace(name) ||
          name.find_first_of("\r\n") != std::string::npos)
        return absl::InvalidArgumentError(
            absl::StrCat("group ", id, ": name '", name,
                         "' cannot be an STL solid name (empty, multi-line or with blanks at "
                         "its ends)"));
  }
  if (ext == ".msh") return CheckMshGroupNames(mesh, names);
  if (ext != ".ply") return absl::OkStatus();
  if (mesh.face_fields.size() > kMaxFaceFields)
    return absl::InvalidArgumentError(
        absl::StrCat("face fields: ", mesh.face_fields.size(), " given, at most ", kMaxFaceFields));
  for (size_t i = 0; i < mesh.face_fields.size(); ++i) {
    const FaceField& field = mesh.face_fields[i];
    const bool blank = std::any_of(field.name.begin(), field.name.end(), [](char c) {
      return absl::ascii_isspace(c) || absl::ascii_iscntrl(c);
    });
    if (field.name.empty() || blank || !IsPlyFieldName(field.name))
      return absl::InvalidArgumentError(absl::StrCat(
          "face field '", field.name,
          "': not usable as a PLY property name (empty, contains blanks, or one of group, "
          "vertex_indices, vertex_index, nx, ny, nz, red, green, blue, alpha)"));
    for (size_t j = 0; j < i; ++j)
      if (mesh.face_fields[j].name == field.name)
        return absl::InvalidArgumentError(
            absl::StrCat("face field '", field.name, "' is given twice"));
    for (size_t f = 0; f < field.values.size(); ++f)
      if (!std::isfinite(field.values[f]))
        return absl::InvalidArgumentError(
            absl::StrCat("face field '", field.name, "': face ", f, " has a non-finite value"));
  }
  return absl::OkStatus();
}

std::string ObjText(const RawMesh& mesh, const GroupNames& names) {
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::string s;
  s.reserve(40 * nv + 24 * nf);
  absl::StrAppend(&s, "# femsimp: ", nv, " vertices, ", nf, " faces\n");
  for (size_t v = 0; v < nv; ++v) {
    s += "v";
    for (int i = 0; i < 3; ++i) {
      s += ' ';
      AppendCoordinate(&s, mesh.origin[i], mesh.positions[3 * v + i]);
    }
    s += '\n';
  }
  const bool groups = !mesh.face_groups.empty();
  for (size_t f = 0; f < nf; ++f) {
    if (groups && (f == 0 || mesh.face_groups[f] != mesh.face_groups[f - 1]))
      absl::StrAppend(&s, "g ", ObjGroupName(mesh.face_groups[f], names), "\n");
    const uint32_t* t = &mesh.triangles[3 * f];
    absl::StrAppend(&s, "f ", uint64_t(t[0]) + 1, " ", uint64_t(t[1]) + 1, " ", uint64_t(t[2]) + 1,
                    "\n");
  }
  return s;
}

std::string OffText(const RawMesh& mesh) {
  std::string s = absl::StrCat("OFF\n", mesh.num_vertices(), " ", mesh.num_faces(), " 0\n");
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) {
      if (k) s += ' ';
      AppendCoordinate(&s, mesh.origin[k], mesh.positions[3 * v + k]);
    }
    s += '\n';
  }
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    absl::StrAppend(&s, "3 ", mesh.triangles[3 * f], " ", mesh.triangles[3 * f + 1], " ",
                    mesh.triangles[3 * f + 2], "\n");
  return s;
}

std::string StlBytes(const RawMesh& mesh, bool binary, const GroupNames& names) {
  const auto corner = [&](size_t f, int k) {
    const float* p = &mesh.positions[3 * mesh.triangles[3 * f + k]];
    return std::array<float, 3>{p[0], p[1], p[2]};
  };
  const auto normal = [&](size_t f) {
    const auto a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double w[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& x : n) x = len > 0 ? x / len : 0.0;
    return std::array<float, 3>{float(n[0]), float(n[1]), float(n[2])};
  };
  // Where the file has a corner: binary STL holds floats, so far from the origin it rounds.
  const auto placed = [&](size_t f, int k) {
    const size_t v = mesh.triangles[3 * f + k];
    return std::array<float, 3>{float(mesh.origin[0] + mesh.positions[3 * v]),
                                float(mesh.origin[1] + mesh.positions[3 * v + 1]),
                                float(mesh.origin[2] + mesh.positions[3 * v + 2])};
  };
  std::string s;
  if (binary && !HasFaceGroups(mesh)) {
    // Sized once and filled in place: 84 header bytes, then 50 per facet.
    static constexpr char kHeader[] = "femsimp binary STL";
    s.assign(84 + 50 * mesh.num_faces(), '\0');
    std::copy(kHeader, kHeader + sizeof(kHeader) - 1, s.begin());
    char* out = s.data() + 80;
    PutLittleEndian(&out, static_cast<uint32_t>(mesh.num_faces()));
    for (size_t f = 0; f < mesh.num_faces(); ++f) {
      for (float x : normal(f)) PutLittleEndian(&out, x);
      for (int k = 0; k < 3; ++k)
        for (float x : placed(f, k)) PutLittleEndian(&out, x);
      out += 2;  // attribute byte count 0
    }
    return s;
  }
  const auto facet = [&](size_t f) {
    s += "facet normal";
    for (float x : normal(f)) (s += ' ', AppendFloat(&s, x));
    s += "\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
      s += "vertex";
      const size_t v = mesh.triangles[3 * f + k];
      for (int i = 0; i < 3; ++i)
        (s += ' ', AppendCoordinate(&s, mesh.origin[i], mesh.positions[3 * v + i]));
      s += '\n';
    }
    s += "endloop\nendfacet\n";
  };
  if (!HasFaceGroups(mesh)) {
    s = "solid femsimp\n";
    for (size_t f = 0; f < mesh.num_faces(); ++f) facet(f);
    return s + "endsolid femsimp\n";
  }
  // Groups as named solids (binary STL has no place for them), in order of first appearance.
  std::vector<uint32_t> order;
  std::map<uint32_t, std::vector<uint32_t>> faces_of;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    std::vector<uint32_t>& faces = faces_of[mesh.face_groups[f]];
    if (faces.empty()) order.push_back(mesh.face_groups[f]);
    faces.push_back(uint32_t(f));
  }
  for (uint32_t group : order) {
    const std::string name = ObjGroupName(group, names);
    absl::StrAppend(&s, "solid ", name, "\n");
    for (uint32_t f : faces_of[group]) facet(f);
    absl::StrAppend(&s, "endsolid ", name, "\n");
  }
  return s;
}

double BinaryStlRounding(const RawMesh& mesh) {
  if (AtOrigin(mesh.origin)) return 0.0;
  double worst = 0.0;
  for (size_t c = 0; c < mesh.positions.size(); ++c) {
    const double at = mesh.origin[c % 3] + double(mesh.positions[c]);
    worst = std::max(worst, std::abs(double(float(at)) - at));
  }
  return worst;
}

std::string PlyBytes(const RawMesh& mesh, bool binary) {
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  const bool groups = !mesh.face_groups.empty();
  // Far from the origin binary coordinates are doubles: floats there would round the part.
  const bool doubles = binary && !AtOrigin(mesh.origin);
  const char* type = doubles ? "double" : "float";
  std::string s = absl::StrCat("ply\nformat ", binary ? "binary_little_endian" : "ascii",
                               " 1.0\ncomment femsimp\nelement vertex ", nv, "\nproperty ", type,
                               " x\nproperty ", type, " y\nproperty ", type, " z\nelement face ",
                               nf, "\nproperty list uchar int vertex_indices\n");
  if (groups) absl::StrAppend(&s, "property uint ", kPlyGroupProperty, "\n");
  for (const FaceField& field : mesh.face_fields)
    absl::StrAppend(&s, "property float ", field.name, "\n");
  s += "end_header\n";
  const size_t face_bytes = 13 + 4 * (groups + mesh.face_fields.size());
  s.reserve(s.size() + (binary ? 12 * nv + face_bytes * nf : 40 * nv + 3 * face_bytes * nf));
  for (size_t v = 0; v < nv; ++v) {
    for (int i = 0; i < 3; ++i) {
      if (doubles) {
        AppendLittleEndian(&s, mesh.origin[i] + double(mesh.positions[3 * v + i]));
      } else if (binary) {
        AppendLittleEndian(&s, mesh.positions[3 * v + i]);
      } else {
        if (i) s += ' ';
        AppendCoordinate(&s, mesh.origin[i], mesh.positions[3 * v + i]);
      }
    }
    if (!binary) s += '\n';
  }
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &mesh.triangles[3 * f];
    if (binary) {
      AppendLittleEndian(&s, uint8_t{3});
      for (int i = 0; i < 3; ++i) AppendLittleEndian(&s, int32_t(t[i]));
      if (groups) AppendLittleEndian(&s, mesh.face_groups[f]);
      for (const FaceField& field : mesh.face_fields) AppendLittleEndian(&s, field.values[f]);
      continue;
    }
    absl::StrAppend(&s, "3 ", t[0], " ", t[1], " ", t[2]);
    if (groups) absl::StrAppend(&s, " ", mesh.face_groups[f]);
    for (const FaceField& field : mesh.face_fields) {
      s += ' ';
      AppendFloat(&s, field.values[f]);
    }
    s += '\n';
  }
  return s;
}

}  // namespace femsimp
