// gmsh MSH 4.1 ASCII (msh.h). Version 4.1 because it is gmsh's own format since gmsh 4 and its
// surface entities carry the physical groups: one entity per face group, so that a group needs no
// tag on each element.
#include <algorithm>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "engine/io/msh.h"

namespace femsimp {
namespace {

// gmsh reads a physical name of at most 127 characters between double quotes on one line.
constexpr size_t kMaxMshName = 127;

// The faces of each group, groups in order of first appearance.
struct GroupFaces {
  std::vector<uint32_t> ids;
  std::vector<std::vector<uint32_t>> faces;
};

GroupFaces FacesByGroup(const RawMesh& mesh) {
  GroupFaces g;
  absl::flat_hash_map<uint32_t, size_t> slot;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t id = mesh.face_groups.empty() ? 0 : mesh.face_groups[f];
    auto [it, fresh] = slot.try_emplace(id, g.ids.size());
    if (fresh) {
      g.ids.push_back(id);
      g.faces.emplace_back();
    }
    g.faces[it->second].push_back(uint32_t(f));
  }
  return g;
}

// A point where the file has it (p relative to the mesh's origin).
void AppendPoint(std::string* s, const RawMesh& mesh, const float* p) {
  for (int k = 0; k < 3; ++k) {
    if (k) *s += ' ';
    AppendCoordinate(s, mesh.origin[k], p[k]);
  }
}

}  // namespace

absl::Status CheckMshGroupNames(const RawMesh& mesh, const GroupNames& names) {
  if (mesh.face_groups.empty() || names.empty()) return absl::OkStatus();
  const absl::flat_hash_set<uint32_t> used(mesh.face_groups.begin(), mesh.face_groups.end());
  for (const auto& [id, name] : names)  // only the names MshText writes
    if (used.contains(id) &&
        (name.size() > kMaxMshName || name.find_first_of("\"\r\n") != std::string::npos))
      return absl::InvalidArgumentError(absl::StrCat(
          "group ", id, ": name '", name.substr(0, 40),
          "' cannot be an MSH physical name (at most 127 characters, no quote, one line)"));
  return absl::OkStatus();
}

std::string MshText(const RawMesh& mesh, const GroupNames& names) {
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  const GroupFaces groups = FacesByGroup(mesh);
  const bool has_groups = HasFaceGroups(mesh);
  std::string s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  s.reserve(s.size() + 48 * nv + 32 * nf);

  // Names of the groups that have faces (gmsh and meshio refuse a name without elements).
  std::vector<uint32_t> named;
  for (uint32_t id : groups.ids)
    if (id != 0 && names.count(id)) named.push_back(id);
  if (!named.empty()) {
    absl::StrAppend(&s, "$PhysicalNames\n", named.size(), "\n");
    for (uint32_t id : named) absl::StrAppend(&s, "2 ", id, " \"", names.at(id), "\"\n");
    s += "$EndPhysicalNames\n";
  }

  // Surface k+1 holds group k's faces; its box is its faces' corners'.
  absl::StrAppend(&s, "$Entities\n0 0 ", groups.ids.size(), " 0\n");
  for (size_t k = 0; k < groups.ids.size(); ++k) {
    std::array<float, 3> lo, hi;
    lo.fill(std::numeric_limits<float>::max());
    hi.fill(std::numeric_limits<float>::lowest());
    for (uint32_t f : groups.faces[k])
      for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 3; ++i) {
          const float x = mesh.positions[3 * mesh.triangles[3 * f + c] + i];
          lo[i] = std::min(lo[i], x);
          hi[i] = std::max(hi[i], x);
        }
    absl::StrAppend(&s, k + 1, " ");
    AppendPoint(&s, mesh, lo.data());
    s += ' ';
    AppendPoint(&s, mesh, hi.data());
    const uint32_t id = groups.ids[k];
    // Group 0 has physical tag 0 when there are groups: meshio refuses a file where only some
    // surfaces have a physical tag, and gmsh reads 0 as one more physical group.
    absl::StrAppend(&s, id != 0 || has_groups ? absl::StrCat(" 1 ", id) : std::string(" 0"),
                    " 0\n");
  }
  s += "$EndEntities\n";

  // Every node in one block on surface 1, tags 1..nv in vertex order.
  absl::StrAppend(&s, "$Nodes\n", nv > 0 ? 1 : 0, " ", nv, " ", nv > 0 ? 1 : 0, " ", nv, "\n");
  if (nv > 0) {
    absl::StrAppend(&s, "2 1 0 ", nv, "\n");
    for (size_t v = 1; v <= nv; ++v) absl::StrAppend(&s, v, "\n");
    for (size_t v = 0; v < nv; ++v) {
      AppendPoint(&s, mesh, &mesh.positions[3 * v]);
      s += '\n';
    }
  }
  s += "$EndNodes\n";

  // Element tag f+1 for face f, so that a reader ordering by tag has the mesh's order.
  absl::StrAppend(&s, "$Elements\n", groups.ids.size(), " ", nf, " ", nf > 0 ? 1 : 0, " ", nf,
                  "\n");
  for (size_t k = 0; k < groups.ids.size(); ++k) {
    absl::StrAppend(&s, "2 ", k + 1, " 2 ", groups.faces[k].size(), "\n");
    for (uint32_t f : groups.faces[k]) {
      const uint32_t* t = &mesh.triangles[3 * f];
      absl::StrAppend(&s, uint64_t(f) + 1, " ", uint64_t(t[0]) + 1, " ", uint64_t(t[1]) + 1, " ",
                      uint64_t(t[2]) + 1, "\n");
    }
  }
  s += "$EndElements\n";
  return s;
}

}  // namespace femsimp
