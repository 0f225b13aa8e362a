// Parts far from the origin (a bolt in plant coordinates, a part in its assembly's frame) are
// held relative to a local origin near them: positions are 32-bit floats, which far from the
// origin are far apart, and would round away detail the file had and the engine's new positions
// alike. Readers choose the origin (LocalOriginOf) when the part lies so far that it matters,
// writers and the wire add it back (RawMesh::origin); a part near the origin keeps origin 0 and
// is held exactly as before.
#pragma once

#include <array>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

// The float spacing at the part's largest coordinate, relative to its diagonal, from which the
// part is held relative to a local origin: some 16 diagonals from the origin. Nearer, floats
// resolve a millionth of the part and nothing is gained by moving it.
inline constexpr double kLocalOriginFrom = 1e-6;

// The local origin for a part in the box [lo, hi]: {0, 0, 0} near the origin (or for an empty or
// pointlike box), else the box's centre with each coordinate rounded to a float, so that a float
// position minus the origin is exact in float again (mesh files of float coordinates move
// without loss).
std::array<double, 3> LocalOriginOf(const double lo[3], const double hi[3]);

// Stores the coordinates (x, y, z per vertex, as a file had them) in mesh->positions relative to
// LocalOriginOf their box, and sets mesh->origin. Coordinates must be finite.
void StoreRelative(const std::vector<double>& xyz, RawMesh* mesh);

// Moves a mesh whose positions are absolute (origin 0) to LocalOriginOf its box: exact, as
// float positions minus a float origin are floats again. A mesh already moved is left alone.
void MoveToLocalOrigin(RawMesh* mesh);

// Expresses the mesh's positions relative to `origin` instead (each rounded to a float): for
// comparing two meshes of one part read from two files, whose origins may differ by a float's
// spacing there.
void ChangeOrigin(RawMesh* mesh, const std::array<double, 3>& origin);

// Whether positions are absolute (the part is held as the file had it).
inline bool AtOrigin(const std::array<double, 3>& origin) {
  return origin[0] == 0.0 && origin[1] == 0.0 && origin[2] == 0.0;
}

// Where vertex v of the mesh lies in the file's (world) coordinates.
inline std::array<double, 3> WorldPoint(const RawMesh& mesh, size_t v) {
  return {mesh.origin[0] + double(mesh.positions[3 * v]),
          mesh.origin[1] + double(mesh.positions[3 * v + 1]),
          mesh.origin[2] + double(mesh.positions[3 * v + 2])};
}

}  // namespace femsimp
