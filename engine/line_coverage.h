// The measured deviation check's hold on feature lines (option deviation_check = measured;
// docs/FIDELITY.md § 1): every point of the input's feature lines (sharp edges, boundaries,
// group borders) stays within the tolerance of the line it became. The surface check alone
// (engine/coverage.h) does not give that: a crease may drift along the surface.
//
// The input's feature edges are cut into pieces (an edge, or a dyadic part of one), and every
// piece is held by one live feature edge within the tolerance of all of it: the distance to a
// segment is convex along a segment, so an edge is within the tolerance of a piece when it is
// of the piece's two ends. A collapse along a line (V slides onto its line neighbour Vd, or V
// and Vd merge at a point P) replaces two or three line edges by one or two; the pieces the old
// edges held go to the new ones, halved where no one new edge takes a whole piece, and a piece
// none takes at the deepest level refuses the collapse.
//
// A live feature edge's pieces are listed at its endpoint with the smaller id, which every
// collapse that changes the edge holds locked: the kernel's locks keep each list to one writer.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "engine/mesh.h"
#include "engine/vec.h"

namespace femsimp {

// A part of an input feature edge: [index, index + 1] / 2^level of the way from its first end.
struct LinePiece {
  uint32_t segment;
  uint16_t level;
  uint16_t index;
};

// One collapse along a line, as the check is given it, and what the check found.
struct LinePlan {
  // The line edges the collapse replaces (vertex id pairs) and the new ones with their ends.
  std::pair<uint32_t, uint32_t> old_edges[3];
  int old_count = 0;
  std::pair<uint32_t, uint32_t> fresh_edges[2];
  DVec3 fresh_from[2], fresh_to[2];
  int fresh_count = 0;
  // Which new edge takes which piece (filled by LineCoverage::Judge); only for a line collapse.
  std::vector<std::pair<int, LinePiece>> given;
  bool active = false;  // the proposal judged last moves a line: its commit applies the plan

  // Scratch, kept with the plan so that its capacity stays.
  std::vector<LinePiece> pending;
};

class LineCoverage {
 public:
  // The mesh's feature edges as they are now are the input lines; each holds itself, whole.
  LineCoverage(const Mesh& mesh, double tolerance);

  // The deepest halving of a piece (2^-level of its edge).
  static constexpr int kMaxLevel = 12;
  // The most pieces one check may look at before it refuses.
  static constexpr uint64_t kMaxWork = 1u << 12;

  // True when every piece the old edges hold is within the tolerance of one new edge; then
  // plan->given says which. Adds the pieces looked at to *work.
  bool Judge(LinePlan* plan, uint64_t* work) const;
  // Under the locks of the collapse that Judge passed: the old edges' lists go to the new edges.
  void Apply(const LinePlan& plan);

  // Every input feature edge is held whole, once over (what the commits built); an internal
  // error naming the first edge that is not.
  absl::Status Audit() const;

  size_t segments() const { return from_.size(); }

 private:
  struct Held {
    uint32_t other;  // the edge's endpoint with the larger id
    LinePiece piece;
  };
  void Ends(const LinePiece& piece, DVec3* a, DVec3* b) const;

  std::vector<DVec3> from_, to_;           // per input feature edge
  std::vector<uint32_t> from_id_, to_id_;  // its vertices in the input, for the audit's message
  std::vector<std::vector<Held>> held_;    // per vertex: the pieces of its edges to larger ids
  double tolerance2_;
};

}  // namespace femsimp
