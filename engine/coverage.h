// The measured deviation check (option deviation_check = measured; docs/FIDELITY.md § 1): every
// collapse is judged against the input itself, so nothing adds up along the run. Two-sided:
//
// (a) Every point of the input stays within the tolerance of the surface. The input's triangles
//     are cut into pieces (a triangle, or one of the four triangles of a piece's midpoint
//     subdivision), and every piece is held by one live face that is within the tolerance of
//     all of it, or by two live faces across an edge, each within the tolerance of the piece's
//     part on its side of a plane through the edge (a pair). The distance to a triangle is
//     convex, so a holder is within the tolerance of a piece (or part) when it is of its
//     corners. A collapse rewrites only the faces of its fan (or
//     star): the pieces those held go to the new faces, cut further where no one new face or
//     pair takes a whole piece; a piece none takes at the deepest level refuses it.
// (b) Every point of a new face lies within the tolerance of the input. The new face is cut the
//     same way; a part is within when its corners all are within the tolerance of one input
//     triangle (convexity), or its parts on either side of the cut between two input triangles
//     across an edge are of theirs, or its centre within the tolerance less the part's radius of
//     one (the distance is 1-Lipschitz), or it lies over a nearly flat, convex fan of an input
//     vertex (Fan below), or over input triangles in a slab (the shadow). The input triangles
//     tried are those of the pieces the old faces held, then all near the new face.
//
// The pieces of a face change only when a collapse holding that face's corners' locks commits,
// so the kernel's locks (and the rounds' disjoint fans) keep every face's list to one writer.
// A pair's piece is listed with both faces; a collapse that rewrites one of them drops it from
// the other's list too, under the locks of the edge the two share, which every collapse
// touching either face holds.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "absl/functional/function_ref.h"
#include "absl/status/status.h"
#include "engine/edge_cut.h"
#include "engine/mesh.h"
#include "engine/star.h"
#include "engine/triangle_distance.h"
#include "engine/vec.h"

namespace femsimp {

// A part of an input triangle: the triangle (level 0) or a child of a part's midpoint
// subdivision, named by the path of child numbers taken from the triangle.
struct Piece {
  uint32_t triangle;
  uint32_t path;  // bits 0-3: the level; bits 4 + 2k and 5 + 2k: the child taken at level k + 1

  int level() const { return static_cast<int>(path & 15u); }
  Piece Parent() const {  // level() > 0
    const uint32_t at = 4 + 2 * (static_cast<uint32_t>(level()) - 1);
    return {triangle, (path & ~(3u << at) & ~15u) | ((path & 15u) - 1u)};
  }
  Piece Child(uint32_t c) const {
    const uint32_t at = 4 + 2 * static_cast<uint32_t>(level());
    return {triangle, (path & ~15u) | c << at | ((path & 15u) + 1u)};
  }
};

// A piece in a face's list: held by that face alone, or together with `partner`, the face
// across one of its edges (a pair: the piece is in the partner's list too).
struct HeldPiece {
  Piece piece;
  uint32_t partner;  // kNone: held alone
};

// What the check of one proposed collapse found, kept for its commit; also its scratch.
struct CoveragePlan {
  struct Given {
    uint32_t holder;   // a new face's index, or past them a kept face's
    uint32_t partner;  // index of the holder across an edge holding it too, or kNone
    Piece piece;
  };
  std::vector<Given> given;
  // Pieces a rewritten face held in a pair with a face the collapse keeps: (that face, the
  // piece), dropped from its list at the commit.
  std::vector<std::pair<uint32_t, Piece>> released;
  // The faces named in `released`, each once: holders beside the new faces (Given's index
  // fresh + k names kept[k]), and per kept face the largest distance it now certifies.
  std::vector<uint32_t> kept;
  std::vector<double> kept_reach;
  // The faces the collapse rewrites or deletes, and the ids of its new faces.
  std::vector<uint32_t> old_faces, fresh_ids;
  // Per new face: the largest distance its certificates leave (both ways), at most the
  // tolerance: the face's measured deviation.
  double reach[kMaxStar];

  // A piece with its corners.
  struct Part {
    Piece piece;
    DVec3 corners[3];
  };
  // The pieces old_faces held, coarsened: every direction of one candidate (and each position
  // of one full-edge collapse) replaces the same faces, which change only under its locks.
  // Forget() when the candidate ends.
  // gathered_star: the Vd of the full-edge collapse they were gathered for (its one-ring's
  // locks are let go between directions), else kNone.
  std::vector<uint32_t> gathered_from;
  std::vector<Piece> gathered;       // coarsened once parts_ready
  std::vector<Part> gathered_parts;  // the same, with their corners, once parts_ready
  // The input vertices at the gathered pieces' corners: (vertex id, its index in the input's
  // corners), one per vertex.
  std::vector<std::pair<uint32_t, size_t>> probes;
  std::vector<uint8_t> probed;  // per input vertex: 1 while it is in probes (scratch)
  uint32_t gathered_star = kNone;
  bool parts_ready = false;  // gathered coarsened and gathered_parts made (past the probes)
  void Forget() { gathered_from.clear(); }

  // Scratch, kept with the plan so that its capacity stays.
  std::vector<Part> pieces;
  std::vector<uint64_t> keys;
  struct Box {
    DVec3 lo, hi;
  };
  // The widened boxes of `under` and `found`, one per triangle, in their order.
  std::vector<Box> under_box, found_box;
  struct Witness {
    uint32_t triangle;
    DVec3 lo, hi;       // its box, widened by the tolerance
    uint32_t distance;  // its index in witness_distance
  };
  std::vector<Witness> witnesses;
  // The distances to the input triangles the check's new faces have looked at, each built once
  // per check (neighbouring new faces share most of theirs), and per input triangle its index
  // there or kNone.
  std::vector<TriangleDistance> witness_distance;
  std::vector<uint32_t> witness_distance_of, witness_distance_slot;
  const TriangleDistance& DistanceTo(const Witness& w) const {
    return witness_distance[w.distance];
  }
  // Per level of a new face's subdivision: the witnesses near the part being judged there.
  std::vector<uint32_t> near[9];
  uint32_t last_witness = 0;
  std::vector<uint32_t> found;
  // Adjacent holders k and j (two corners the same; k a new face): a piece whose part on each
  // side of the cut between them is within the tolerance of that side's face (engine/edge_cut.h)
  // is held by the two. Found once per check, when a piece first needs them.
  struct HolderPair {
    int k, j;
    EdgeCut cut;
    DVec3 lo, hi;  // the two faces' box, widened by the tolerance
  };
  std::vector<HolderPair> holder_pairs;
  bool holder_pairs_found = false;
  // The holders' corners (3 per new face, then 3 per kept face) and distances.
  std::vector<DVec3> holder_corners;
  std::vector<TriangleDistance> to_holder;
  std::vector<DVec3> holder_box;  // per holder: its box widened by the tolerance, lo then hi
  // Per holder: the squared distances of the piece's first known_count corners to it, as the
  // test of single holders computed them (3 per holder).
  std::vector<double> known;
  std::vector<uint8_t> known_count;
  std::vector<uint32_t> under;  // the input triangles of the pieces given, each once
  // The input triangles the shadow certificate has looked at; member: in the part's slab,
  // facing its way, its shadow meeting the part's box.
  struct Point2 {
    double x, y;
  };
  struct Shade {
    uint32_t triangle;
    bool member;
    double height;  // the largest distance of its corners from the part's plane
    Point2 xy[3];   // its corners seen along the part's normal
  };
  std::vector<Shade> shade;
  std::vector<uint32_t> shade_slot;  // per input triangle: its index in shade, or kNone
  // (b)'s tolerance for the new face being judged, and its square: the run's, or with the faces'
  // own limits (the wall rule) the least limit of the pieces the face takes; per new face.
  double limit = 0, limit2 = 0;
  double fresh_limit[kMaxStar];
};

// The shadow certificate's clip (engine/coverage_shadow.cc): the largest |height| over the part
// of the counter-clockwise triangle xy (heights at its corners, affine between) whose shadow
// lies in the counter-clockwise triangle r; negative when none does.
double ClippedHeight(const CoveragePlan::Point2 xy[3], const double height[3],
                     const CoveragePlan::Point2 r[3]);

class Coverage {
 public:
  // The mesh's live faces as they are now are the input; each holds itself, whole. The mesh
  // is the one simplified: the faces a collapse keeps are read from it, and their errors
  // raised where they come to hold more (Apply). With face_limits, each input triangle keeps
  // its face's own tolerance where that is lower (FaceAttrQ::limit, the wall rule's; 0: none):
  // its pieces are held within it, and a new face is judged in (b) against the least limit of
  // the pieces it takes.
  Coverage(Mesh& mesh, double tolerance, bool face_limits = false);

  // The deepest subdivision of a piece, and of a new face (2^-level of its edges).
  static constexpr int kMaxPieceLevel = 12;
  static constexpr int kMaxPartLevel = 7;  // CoveragePlan::near has a list per level
  // The most pieces and parts one check may look at before it refuses (it cannot prove the
  // collapse within the tolerance cheaply enough).
  static constexpr uint64_t kMaxWork = 1u << 14;

  // True when (a) and (b) hold for the collapse that replaces plan->old_faces by new faces with
  // these corners; then `plan` says which new face takes which piece.
  // fresh_corners holds 3 corners per new face; plan->old_faces names the old faces.
  // certify, called once (a) holds: fills, per new face, a distance within which every point of
  // it is known to lie of the input, and returns true, or returns false when it knows none;
  // (b) takes a new face certified within the tolerance as it is.
  using Certify = absl::FunctionRef<bool(double* certified)>;
  bool Judge(
      std::span<const DVec3> fresh_corners, CoveragePlan* plan, uint64_t* work,
      Certify certify = [](double*) { return false; }) const;
  // The commit: the old faces drop their pieces, new face k (id plan.fresh_ids[k]) takes those
  // the plan gave it.
  void Apply(const CoveragePlan& plan);

  // The pieces face f holds, alone or in a pair (tests, statistics).
  std::vector<HeldPiece> Held(uint32_t f) const;
  // Checks what the commits built (tests, and the end of every measured run): every input
  // triangle's area is the sum of its pieces', each listed once (a pair's in both faces'
  // lists, each naming the other), every holder live in the mesh and within the tolerance of
  // its pieces' corners (a pair: each of the two within it of the piece's part on its side of
  // the cut). Internal error naming the first piece that is not.
  absl::Status Audit() const;
  // The corners of a piece.
  void Corners(Piece piece, DVec3 out[3]) const;

 private:
  template <class Visit>
  void ForEachHeld(uint32_t f, Visit&& visit) const {
    if (whole_[f]) {
      visit(HeldPiece{Piece{f, 0}, kNone});
      return;
    }
    for (const HeldPiece& p : held_[f]) visit(p);
  }
  // The holders across an edge from each other (one of them new), into plan->holder_pairs.
  void FindHolderPairs(int fresh, CoveragePlan* plan) const;
  // The piece with corners c (c_box their box) taken by one of plan->holder_pairs whole, each
  // side within sqrt(limit2): its index, and in *reach the largest distance certified, or -1.
  // to: the holders' distances.
  int TakeByPair(const DVec3* c, const CoveragePlan::Box& c_box, const TriangleDistance* to,
                 double limit2, CoveragePlan* plan, int* last_pair, double* reach) const;
  // (b) for the new face with corners p[0..2], against plan->witnesses: its certified reach,
  // or a negative number when some part is not within plan->limit.
  double Within(const DVec3* p, CoveragePlan* plan, uint64_t* work) const;
  // The part with corners c within sqrt(limit2) of input face `face` and one across an edge of
  // it, together: its reach, or negative.
  double WithinPair(const DVec3* c, uint32_t face, double limit2) const;
  double WithinPart(const DVec3* c, int level, CoveragePlan* plan, uint64_t* work) const;
  // The part with corners c within `limit` of input vertex v's fan, flat and convex seen along
  // its normal: its reach, or negative.
  double WithinFan(const DVec3* c, uint32_t v, double limit) const;
  // The part with corners c within plan->limit of the input triangles straight below or above
  // it (engine/coverage_shadow.cc), starting from the witnesses `seeds`: its reach, or negative.
  // Counts one work unit per 16 triangles looked at.
  double WithinShadow(const DVec3* c, std::span<const uint32_t> seeds, CoveragePlan* plan,
                      uint64_t* work) const;
  // (b)'s tolerance per new face (plan->fresh_limit), from the pieces plan->given gives them.
  void LimitFreshFaces(int fresh, CoveragePlan* plan) const;
  // The most input triangles one shadow certificate looks at.
  static constexpr size_t kMaxShade = 4096;

  // The boxes of `triangles`, widened by the tolerance.
  void WidenedBoxes(std::span<const uint32_t> triangles,
                    std::vector<CoveragePlan::Box>* boxes) const;
  // The triangles (ids, each once; `boxes` their widened boxes) whose widened boxes meet the
  // box [lo, hi], into plan->witnesses (with their widened boxes).
  void Witnesses(const DVec3& lo, const DVec3& hi, std::span<const uint32_t> triangles,
                 std::span<const CoveragePlan::Box> boxes, CoveragePlan* plan) const;
  // The same for every input triangle (from the grid).
  void GridWitnesses(const DVec3& lo, const DVec3& hi, CoveragePlan* plan) const;
  void IndexInput();
  // pair_far_, for WithinPair.
  void FindFarCorners();
  void MeasureFans(const Mesh& mesh);
  // Replaces every four children of one piece by that piece, as long as there are such (keys:
  // scratch).
  static void Coarsen(std::vector<Piece>* pieces, std::vector<uint64_t>* keys);

  Mesh* mesh_;
  std::vector<Vec3> input_;       // 3 corners per face id (the input's faces)
  std::vector<uint32_t> across_;  // 3 per face: the input face across each edge (kNone: none)
  // Per face edge: the corner of the face across that is not on the edge (kNoFar: no face
  // across, or it shares more than the edge).
  static constexpr uint8_t kNoFar = 3;
  std::vector<uint8_t> pair_far_;
  // An input vertex's fan that its normal n sees as a convex polygon, each point of it once,
  // and whose corners lie in the slab lo <= n.(x - centre) <= hi thinner than the tolerance: every
  // point whose shadow along n falls in the polygon is within its slab distance plus hi - lo of the
  // fan. The polygon's corners, in the (u, w) plane, counter-clockwise, are
  // fan_points_[2 * first .. 2 * (first + count)).
  struct Fan {
    DVec3 centre, n, u, w;
    double lo, hi;
    uint32_t first, count;
  };
  std::vector<uint32_t> corner_vertex_;  // 3 per face id: the input vertex at each corner
  std::vector<uint32_t> fan_of_;         // per input vertex: its index in fans_, or kNone
  std::vector<Fan> fans_;
  std::vector<double> fan_points_;
  // A uniform grid over the input triangles (they never change: read without locks): cell
  // (x, y, z) lists cell_faces_[cell_start_[c] .. cell_start_[c + 1]).
  DVec3 origin_{0, 0, 0};
  double cell_ = 1.0;
  int64_t dims_[3] = {1, 1, 1};
  std::vector<uint32_t> cell_start_, cell_faces_;
  std::vector<std::vector<HeldPiece>> held_;
  // 1: the face still holds exactly its own input triangle (no list yet). Bytes, not bits:
  // contexts write different faces' flags at once.
  std::vector<uint8_t> whole_;
  double tolerance_;
  double tolerance2_;
  // Per input triangle: its tolerance, lowered as tolerance_ is, and its square; empty when
  // every triangle has the run's.
  std::vector<double> limit_, limit2_;
  double Limit2(uint32_t triangle) const {
    return limit2_.empty() ? tolerance2_ : limit2_[triangle];
  }
};

}  // namespace femsimp
