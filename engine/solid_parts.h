// The parts of an assembly as solids (docs/FIDELITY.md § 8). Parts that share a face or an edge
// meet at seams, where SplitSeams cuts the soup into open sheets: no sheet encloses a volume,
// yet the assembly does, part by part. Around every seam edge the faces are sorted by angle, so
// that each wedge of space between two neighbours joins the sides of the two faces that face
// it; across an ordinary edge the two faces' fronts join, and their backs. The sides so joined
// are the regions of space the soup bounds: in each connected piece with a seam, one region is
// unbounded (its boundary's signed volume is negative) and the others are the parts.
//
// A sheet's faces all see the same two regions (they are joined across ordinary edges), so a
// collapse, which rewrites faces of one sheet, changes the volume of the part behind it by the
// volume it sweeps and that of the part ahead of it by the opposite.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/edge_groups.h"
#include "engine/raw_mesh.h"
#include "engine/vec.h"

namespace femsimp {

struct SolidParts {
  std::vector<uint32_t> face_sides;  // per face: an index into `sides`
  std::vector<FaceSides> sides;      // the distinct pairs, in the order faces first use them
  std::vector<double> volumes;       // per part, of the soup
  size_t parts() const { return volumes.size(); }
};

// Empty (no sides, no parts) unless the soup has a non-manifold edge and bounds solids there:
// no edge has a single face, and in every connected piece with a seam each face has different
// regions on its two sides, exactly one region is unbounded and every other encloses a
// positive volume. Faces of pieces without a seam (a separate body, the wall of a cavity) get
// no part and weight +1: the repair has oriented them to bound their volume, cavities facing
// in. Indices must be in range (as after RepairMesh). `edges`: the soup's edge groups when the
// caller has them, else made here.
SolidParts FindSolidParts(const RawMesh& mesh, const EdgeGroups* edges = nullptr);

// The centre of the box around the soup's faces: parts' volumes are measured about it, so that
// no large terms cancel. The soup must have a face.
DVec3 SoupCentre(const RawMesh& mesh);

}  // namespace femsimp
