// Faces of a triangle soup that cross each other, or overlap within one plane: the checks an FE
// mesher makes first (tetgen refuses a surface that intersects itself, and overlapping facets). The
// collapses never make a crossing (the self-intersection rule, docs/FIDELITY.md § 9), so crossings
// in an output came with its input (a thin wall exported with facets as large as the part) or from
// a run that allowed them; the CLI and the server report them with the output so that the analyst
// hears of them before the mesher says so.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp {

class WorkerPool;

struct SoupCrossings {
  uint64_t pairs = 0;  // face pairs that certainly cross (engine/transversal_crossing.h)
  // The scan stopped once more pairs than CrossingScan::stop_after crossed: this count, and
  // those of overlaps and folds below, are floors.
  bool cut_short = false;
  // The first such pair in face order (lowest face, then lowest partner), and a point where they
  // cross; meaningful when pairs > 0.
  uint32_t face_a = 0, face_b = 0;
  std::array<double, 3> at{};
  // Face pairs with no corner in common, in one plane, whose insides overlap
  // (engine/planar_overlap.h): bodies exported apart that touch, their contact triangulated
  // twice; the first pair as above, a point of their common part, and the area of every pair's
  // common part (the contact's area: each point of a contact is under one face of each body,
  // less what pairs with a corner welded in common overlap). Faces in one plane with a corner
  // in common overlap only where a surface folds onto itself, which this leaves out.
  struct Overlaps {
    uint64_t pairs = 0;
    uint32_t face_a = 0, face_b = 0;
    std::array<double, 3> at{};
    double area = 0.0;
  } overlaps;
  // Face pairs with an edge in common, in one plane, facing opposite ways: one turned over onto
  // the other (a fold, engine/fold.h), which FE meshers refuse as they do an overlap. Repair
  // unfolds what a flip of the edge undoes (engine/repair.h) and the collapses make none, so
  // these came with the input; the first pair as above and the middle of their common edge.
  struct Folds {
    uint64_t pairs = 0;
    uint32_t face_a = 0, face_b = 0;
    std::array<double, 3> at{};
  } folds;
};

// How far off a face's plane a point of a planar contact may lie: a millionth of the diagonal,
// or a few float spacings of the largest coordinate, whichever is larger (contacts exported
// apart are planar up to their corners' rounding to float).
double ContactPlaneTolerance(const RawMesh& soup);

// Every pair of faces whose bounding boxes overlap is tested once: with an edge in common, a fold
// when IsFold says so (faces running their edge the same way, misoriented, face no way and
// are never one); else an
// overlap when they share no corner, each has its corners within a millionth of the diagonal (or a
// few float spacings of the coordinates) of the other's plane and their insides overlap, else a
// crossing when TransversalCrossing says so (only certain crossings count, not contacts) and each
// face reaches through the other's plane by more than that tolerance on both its sides (a face
// standing on another along a tilted contact pokes through it by its corners' rounding). The pairs
// are found through a uniform grid of cells about twice the mean edge (coarser where large faces
// would span many cells). `lists`, when given, receives every pair of each kind (lower face
// first), in no particular order: what an imprint re-tiles (the overlaps, engine/imprint.h) and
// what the repair takes out and closes again (the crossings, engine/crossing_repair.h).
struct CrossingPairLists {
  std::vector<std::pair<uint32_t, uint32_t>> crossing, overlapping, folded;
};

// Enough crossing pairs to know what the surface is: a soup of facets, or bodies exported
// overlapping (one vertex written wrongly makes a few dozen), where every pair would take
// minutes to hours to count (20,000 random facets: 56 million pairs, 34 s). The repair's scan
// and the output's check stop there.
inline constexpr size_t kEnoughCrossingPairs = 100000;

struct CrossingScan {
  CrossingPairLists* lists = nullptr;
  bool crossings_only = false;  // the crossings alone: no fold or overlap tested, none counted
  // The scan stops once more crossing pairs than this are found (SoupCrossings::cut_short), at
  // the end of the stretch of cells where the count passed it.
  size_t stop_after = std::numeric_limits<size_t>::max();
  // The cells are scanned on its contexts (none: on the caller alone); the result is the same
  // on any number of threads.
  WorkerPool* pool = nullptr;
};
SoupCrossings FindCrossings(const RawMesh& soup, const CrossingScan& scan = {});

// The check of an output before it is written (the CLI's and the server's): every kind, on
// `threads` threads, stopped at kEnoughCrossingPairs.
SoupCrossings CheckOutputCrossings(const RawMesh& output, int threads);

// "N face pairs cross (the first: faces A and B, at (x, y, z))": the words every report of them
// uses (the summary, the FE check's refusal); meaningful when pairs > 0. Each count reads "at
// least N" where the scan was cut short.
std::string DescribeCrossings(const SoupCrossings& c);

// "N face pairs overlap in their plane, over an area of A (the first: faces A and B, at (x, y,
// z)): bodies exported apart that touch, ..."; meaningful when overlaps.pairs > 0.
std::string DescribeOverlaps(const SoupCrossings& c);

// "N face pairs lie on each other in their plane, one of each turned over (the first: faces A
// and B, along their common edge at (x, y, z))"; meaningful when folds.pairs > 0.
std::string DescribeFolds(const SoupCrossings& c);

}  // namespace femsimp
