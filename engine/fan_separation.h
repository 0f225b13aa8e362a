// Faces beside a collapse's fan, seen along the fan's normal: shows that a face near a half-edge
// collapse meets none of its new triangles without testing it against each of them.
//
// Seen along the summed normal n of V's closed fan, let the one-ring be a polygon P winding once
// around V and star-shaped around it, and H its convex hull (P itself where P is convex). Where
// every new triangle (Vd, nbr[f], nbr[f + 1]) of a direction is clearly counter-clockwise
// (Covers), they cover each point of P once (P's winding number there) and nothing outside it:
// each lies in P, inside H, and is seen one to one. A face F can then meet a new triangle T only
// where their projections meet, and where those meet only in a corner or an edge they share, F
// and T meet only there. F's projection stays out of H but for what F shares with the ring when:
//   - F shares no corner with the ring: its corners lie all above or all below the ring's
//     heights along n (a new triangle's heights are its ring corners'), or all beyond the line
//     of one side of H;
//   - F shares one ring corner r, a corner of H: H's angle at r and F's (both convex) meet only
//     at r, each side of either strictly outside the other (two convex angles with one apex
//     that hold no side of each other meet only there); r, extreme in H, is in a new triangle
//     only as its corner;
//   - F shares a side of P that is a side of H: its third corner lies strictly beyond that
//     side's line.
// "Strictly" means by a relative margin (1e-8) far above the rounding of these figures and above
// the near-touch band of the triangle test (engine/triangle_intersection.h, 1e-12 of the
// lengths). That test is conservative near degenerate pairs, so a face shown apart here can be
// one it would call meeting (docs/FIDELITY.md § 9: such pairs are apart by CGAL's exact
// predicates); tests/engine/fan_separation_test.cc checks on random fans that no face shown
// apart meets a new triangle. A false answer means "not shown": the face is tested as before.
#pragma once

#include <cstdint>

#include "engine/ring.h"
#include "engine/triangle_intersection.h"
#include "engine/vec.h"

namespace femsimp {

class FanSeparation {
 public:
  // Sets up for V's fan, whose ring corners have the point ids ids[i] (the ids the triangle test
  // compares). False: not shown for this fan (a boundary fan, a ring that does not clearly wind
  // once around V seen along n, a hull with a corner not clearly convex); Apart must not be
  // called then.
  bool Prepare(const Ring& fan, const uint32_t* ids);
  // Whether every new triangle of the collapse onto nbr[target] is clearly counter-clockwise
  // seen along n, so that Apart holds for them.
  bool Covers(int target) const;
  // Whether `face` (corners named by point ids) certainly meets no new triangle of a direction
  // Covers accepts beyond the corners and edges it shares with it. *tests counts the 2D
  // orientation tests made (the cell back end's cycle model).
  bool Apart(const Triangle& face, int* tests) const;

 private:
  struct Flat {
    double x, y;
  };
  Flat Project(const DVec3& q) const { return {Dot(q, e1_), Dot(q, e2_)}; }
  bool ConeApart(int r, const Flat& a, const Flat& b, int* tests) const;
  bool BeyondASide(const Flat f[3], int* tests) const;

  int corners_ = 0;
  DVec3 origin_{}, e1_{}, e2_{}, n_{};
  Flat ring_[kMaxRing];
  uint32_t id_[kMaxRing];
  double low_ = 0, high_ = 0;  // the ring's heights along n
  double extent_ = 0;          // the ring's largest coordinate offset from V
  int hull_[kMaxRing];         // the ring corners on its convex hull, counter-clockwise
  int hull_size_ = 0;
  int hull_at_[kMaxRing];  // where ring corner i is in hull_, or -1
};

}  // namespace femsimp
