// Duplicate bodies: a closed body written twice, as exports of assemblies carry them (a part
// inserted twice at one place, a body exported again beside itself, one copy tessellated anew
// or moved by a placement's rounding). The copies cross each other everywhere, so the mesh
// cannot be tet-meshed and its volume and moments count the body twice; the repair stage keeps
// the first and removes the others, and says so (RepairKind::kDuplicateBody,
// RepairOptions::duplicate_body_offset).
//
// A shell is a surface (engine/surfaces.h) closed by itself: each of its edges has two of its
// facets, running it opposite ways once they are turned alike (the step runs before the
// orientation), so a copy sharing an edge or a corner with the first still counts. A later shell
// is a copy of an earlier one when their boxes are within d on every side, every corner and
// facet centroid of each lies within d of the other's surface, and each has such a sample
// outside the other (they cross: a shell inside another near its surface is the wall of a thin
// cavity, or a coating's outer wall over a part); d is `max_offset` times the thinner one's
// mean thickness 2V/A. Plates stacked on each other (2V/A apart) are not copies; nor are two
// shells with a third near both that repeats neither (layers: a coating's inner wall on a part,
// its outer wall around both).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace femsimp {

struct DuplicateBody {
  std::vector<uint32_t> faces;     // of the copy removed, ascending
  uint32_t kept_face = 0;          // the first facet of the body it repeats (which is kept)
  uint32_t kept_faces = 0;         // that body's facet count
  double distance = 0;             // the farthest sample of either from the other
  double thickness = 0;            // 2V/A of the thinner of the two
  double volume = 0;               // the copy's, unsigned
  std::array<double, 3> centre{};  // the copy's area-weighted facet centroid
};

// `tri`: three vertex ids per facet, in any orientation; `edge_of` and `edge_uses` as
// engine/surfaces.h takes them. Copies in order of their first facet, each repeating an earlier
// body that is kept; `max_offset` 0 finds none.
std::vector<DuplicateBody> FindDuplicateBodies(const float* positions,
                                               std::span<const uint32_t> tri,
                                               std::span<const uint32_t> edge_of,
                                               std::span<const uint32_t> edge_uses,
                                               double max_offset);

}  // namespace femsimp
