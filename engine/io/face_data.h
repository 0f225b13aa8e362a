// Face groups and face fields in mesh files: which format holds what, the naming rules shared by
// the readers (mesh_readers.cc) and the writers, and femsimp's writers of OBJ, PLY, OFF and STL
// (MSH's: msh.h).
//
//   format  face groups                               face fields
//   OBJ     `g NAME` statements                        -
//   PLY     integer face property `group`              float/double face properties, by name
//   MSH     physical groups (msh.h)                    -
//   STL     ASCII `solid NAME` per group (so written     -
//           ASCII when the mesh has groups)
//   OFF     -                                          -
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// Names of face groups by id, for formats that name groups (OBJ, MSH's $PhysicalNames, STL's
// solids). Ids missing
// here are written with their default name (ObjGroupName).
using GroupNames = std::map<uint32_t, std::string>;

// ------------------------------------------------------------------------------------ OBJ
//
// Group names (OBJ's and ASCII STL's: a file of one solid has no groups) and ids map as follows, so
// that every id survives a write and a read:
//   "default" (the OBJ name of faces before any `g`, and of a `g` without a name) <-> id 0,
//   "group_<n>" (n in decimal, no leading zeros)                                   <-> id n,
//   any other name -> the lowest id from 1 up that no name of the file takes, in order of first
//   appearance; the name is kept in GroupNames, and written back for that id.
// A `g` with several names (OBJ's "member of several groups") is one group named by all of them,
// joined with single spaces: a femsimp face belongs to exactly one group.
inline constexpr char kObjDefaultGroup[] = "default";

// The name written for `id`: its entry in `names`, else "default" for 0 and "group_<id>".
std::string ObjGroupName(uint32_t id, const GroupNames& names);

// Ids for the distinct names of one file, in order of first appearance (rules above). Only the
// names that are not "default" or "group_<n>" are added to `names`.
std::vector<uint32_t> ObjGroupIds(const std::vector<std::string>& distinct_names,
                                  GroupNames* names);

// ------------------------------------------------------------------------------------ PLY
//
// Face property "group" (any integer type, values in [0, 2^32)) holds the group ids. Every other
// scalar face property of type float or double is a face field named like the property, except
// the normal (nx, ny, nz) and colour (red, green, blue, alpha) properties other tools write;
// integer face properties other than "group" are ignored.
inline constexpr char kPlyGroupProperty[] = "group";

// True when a scalar float/double face property of this name is read as a face field.
bool IsPlyFieldName(absl::string_view name);

// ------------------------------------------------------------------------------ all formats

// Face groups count as present when any face has a group other than 0 (the engine's "no group";
// Mesh::ToRaw drops an all-zero list the same way).
bool HasFaceGroups(const RawMesh& mesh);

// Fails with InvalidArgument naming the format, what it cannot hold and where it could go, when
// the format of `ext` (lower-case, with the dot) cannot hold the mesh's groups or fields.
absl::Status CheckFormatHolds(absl::string_view ext, const RawMesh& mesh);

// Clears what the format of `ext` cannot hold (for a caller that chose to drop it).
void DropUnheldFaceData(absl::string_view ext, RawMesh* mesh);

// The whole file, for a well-formed soup that passed CheckFaceData. OBJ: text with `g` lines where
// the group changes (when the mesh has groups). PLY: binary little-endian or ASCII, with the group
// and field properties.
std::string ObjText(const RawMesh& mesh, const GroupNames& names);
std::string PlyBytes(const RawMesh& mesh, bool binary);
// OFF as text (shortest exact floats); STL binary (little-endian) or ASCII, normals computed;
// a mesh with groups as ASCII STL, one solid per group named as in OBJ (ObjGroupName).
std::string OffText(const RawMesh& mesh);
std::string StlBytes(const RawMesh& mesh, bool binary, const GroupNames& names);

// How far binary STL's absolute float coordinates put a vertex from where the mesh has it (0 at
// origin 0): the largest rounding of any coordinate, in model units.
double BinaryStlRounding(const RawMesh& mesh);

// Appends the shortest decimal that reads back as the same float (the writers' number text).
void AppendFloat(std::string* s, float v);

// Appends a coordinate where the file has it, origin + position (RawMesh::origin): at origin 0
// the float's shortest text; else the shortest text that reads back to the same position
// relative to the origin, as the readers read it.
void AppendCoordinate(std::string* s, double origin, float position);

// What the writers need beyond a well-formed soup: finite field values; for PLY, field names
// that read back as fields (IsPlyFieldName, no blanks); for OBJ, group names on one line; for MSH,
// group names that fit gmsh's quotes (CheckMshGroupNames).
absl::Status CheckFaceData(absl::string_view ext, const RawMesh& mesh, const GroupNames& names);

}  // namespace femsimp
