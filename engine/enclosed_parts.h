// Parts for bodies that share their whole surface with a body around them: an insert, a core, a
// part under a coating (docs/FIDELITY.md § 8). Each body was written closed on its own, so the
// surface came twice, facing both ways; the repair kept it once, facing into the inner body as
// the outer body's wall faced (RepairResult::shared_shells). No edge of it is a seam, so
// FindSolidParts sees none of it and the inner body would pass for a cavity. Here the outer body
// becomes a part, bounded by its outer shell and the walls of its cavities, and each inner body
// another, with the shared surface between the two (weight 0).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/raw_mesh.h"
#include "engine/solid_parts.h"

namespace femsimp {

struct EnclosedParts {
  SolidParts parts;                  // empty (no sides, no parts) where no surface was made parts
  std::vector<int32_t> shell_sides;  // per surface asked about: its faces' index into
                                     // parts.sides, or -1 where it stays a cavity's wall
};

// `shell_vertices`: a vertex of each shared surface. The closed components nest by winding
// numbers (each one's parent the smallest around it); inside a component facing outward lies a
// body, inside one facing into itself a cavity, or an inner body where it is a shared surface
// with a body (outer or inner) around it. In every tree of nesting that holds an inner body,
// each body and inner body is a part, bounded by its own surface and its children's; the other
// trees, and a tree with a body facing outward inside material (bodies crossing), keep no part
// and weight +1. Nothing is made where an edge has three or more faces (seams: FindSolidParts'
// case).
EnclosedParts FindEnclosedParts(const RawMesh& mesh, const std::vector<uint32_t>& shell_vertices);

}  // namespace femsimp
