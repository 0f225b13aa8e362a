// Faces of a triangle soup that cross each other: the check an FE mesher makes first (tetgen
// refuses a surface that intersects itself). The collapses never make a crossing (the
// self-intersection rule, docs/FIDELITY.md § 9), so crossings in an output came with its
// input (a thin wall exported with facets as large as the part) or from a run that allowed
// them; the CLI and the server report them with the output so that the analyst hears of them
// before the mesher says so.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "engine/raw_mesh.h"

namespace femsimp {

struct SoupCrossings {
  uint64_t pairs = 0;  // face pairs that certainly cross (engine/transversal_crossing.h)
  // The first such pair in face order (lowest face, then lowest partner), and a point where they
  // cross; meaningful when pairs > 0.
  uint32_t face_a = 0, face_b = 0;
  std::array<double, 3> at{};
};

// Every pair of faces whose bounding boxes overlap is tested once (TransversalCrossing: only
// certain crossings count, not contacts or folds within one plane), found through a uniform grid
// of cells about twice the mean edge (coarser where large faces would span many cells).
SoupCrossings FindCrossings(const RawMesh& soup);

// "N face pairs cross (the first: faces A and B, at (x, y, z))": the words every report of them
// uses (the summary, the FE check's refusal); meaningful when pairs > 0.
std::string DescribeCrossings(const SoupCrossings& c);

}  // namespace femsimp
