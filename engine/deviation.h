// The guaranteed deviation bound of a half-edge collapse (docs/FIDELITY.md).
//
// Every live face f carries what is known of a continuous map phi from the input surface onto
// the current one, for the points p that phi maps onto f: |phi(p) - p| <= e_f, and phi(p) - p
// lies in an axis-aligned box. Such a map bounds the two-sided Hausdorff distance by max e_f. A
// collapse V -> Vd replaces V's fan (the old patch) by Vd's new faces (the new patch) inside the
// same link polygon; BoundDeviation builds the next map there: both patches are laid out in one
// plane (the old one with V moved to V', its closest point on the feature line when V slides along
// one), points with the same plane position correspond, and the displacement, affine on every cell
// of the overlay of the two layouts, is largest at a cell corner: V', a crossing of an old and a
// new spoke, or a link vertex (which does not move). On a new face, phi(p) - p is an old
// displacement plus the step of the overlay cell holding p: the new box is the union, over the old
// faces it overlaps, of the old box plus the box of the cell's corner steps, and the new bound the
// smaller of the box's farthest corner and the largest old bound plus the largest step. The box
// keeps steps in different directions (and in and out) from adding up as lengths do. Local to the
// one-ring, so it runs in parallel.
#pragma once

#include <limits>

#include "engine/ring.h"
#include "engine/star.h"
#include "engine/vec.h"

namespace femsimp {

// What is known of phi(p) - p for the points p that phi maps onto one face.
struct Displacement {
  double bound = 0.0;              // |phi(p) - p| <= bound
  DVec3 lo{0, 0, 0}, hi{0, 0, 0};  // phi(p) - p lies in [lo, hi]
  // The smallest tolerance of its own that one of those points p has (the wall rule's,
  // engine/rules/wall_share.cc): a new face takes the least of the old faces it overlaps.
  double limit = std::numeric_limits<double>::infinity();
  double Reach() const;  // the box's farthest point from 0
};

// A point of the layout plane.
struct PlanePoint {
  double x, y;
};

// V's fan laid out in the plane perpendicular to its area-weighted normal: what BoundDeviation
// needs of the fan alone, the same for every direction of one candidate, so laid out once.
struct FanLayout {
  bool ok = false;  // false: the fan has no normal (every direction is refused)
  DVec3 v, u, w;    // V, and the plane's basis
  DVec3 p[kMaxRing + 1];
  PlanePoint q[kMaxRing + 1];  // p[k] - V in the plane
  double scale = 0.0, eps_len = 0.0, eps_area = 0.0;
  bool winds_around_v = false;  // every fan face counter-clockwise around V itself
  // The angles of the fan's faces at V summed, once a direction that leaves V' at V asks
  // (every such direction's winding test sums the same; < 0: not yet).
  mutable double angle_at_v = -1.0;
};
void LayOutFan(const Ring& ring, FanLayout* layout);

// One direction V -> nbr[target] in the fan's layout: where V goes (V', v2 in the plane), the
// faces that survive, and the step at V' on the new faces holding its position.
struct DirectionLayout {
  PlanePoint v2, qd;
  bool survives[kMaxRing];
  bool holds_v[kMaxRing];
  DVec3 step_v[kMaxRing];
};
// The refusals BoundDeviation makes before it lays the two patches over each other (the layouts
// cannot tile, or V' alone takes a new face beyond the limit), at a fraction of its cost: false
// exactly where those refuse (then *work counts what was tested). The kernel runs it on a
// direction before it reads Vd's ring.
bool LayOutDirection(const Ring& ring, const FanLayout& fan, int target, int line_other,
                     const Displacement* old_moved, double limit, DirectionLayout* direction,
                     int* work);

// old_moved[f]: fan face f's displacement. On success fills new_moved[f] for every fan face that
// survives (the two containing V - Vd are deleted) and returns true; returns false when the
// layouts do not tile the link polygon (the map cannot be built: the collapse is refused).
// line_other: index of V's other feature neighbour when V slides along a feature line, or -1.
// limit: returns false early once some new face's bound is sure to exceed it (pass infinity
// to have every bound computed). *work counts the elementary tests (the cell back end's cycle
// model).
bool BoundDeviation(const Ring& ring, int target, int line_other, const Displacement* old_moved,
                    double limit, Displacement* new_moved, int* work);
// The same, the fan and the direction laid out already (LayOutDirection accepted it).
bool BoundDeviation(const Ring& ring, const FanLayout& fan, const DirectionLayout& direction,
                    int target, const Displacement* old_moved, double limit,
                    Displacement* new_moved, int* work);

// Distances instead of a map: every point of old fan face f lies within old_reach[f] of some
// set (the input, for the measured check). Then every point x of a surviving face lies within
// new_reach[f] of it: the overlay pairs x with a point y of an old face f whose step x - y lies
// in its cell's box, and y lies within old_reach[f] of the set, so BoundDeviation with old bound
// old_reach[f] and the cube of that half-side for its box bounds |x - p| for p the set's point
// nearest y. False when the overlay cannot be built.
bool BoundReach(const Ring& ring, int target, int line_other, const double* old_reach,
                double* new_reach);

// The same for a full-edge collapse (engine/star.h): both patches are projected onto the plane
// perpendicular to the old star's area-weighted normal, where each must tile the link polygon
// (every triangle counter-clockwise, the angles around V, Vd and P each a full turn), points
// with the same projection correspond, and the displacement, affine on every cell of the
// overlay, is largest at a cell corner: a corner of either triangle inside the other, or a
// crossing of their edges. old_moved / new_moved are indexed by star face (new_moved for the
// faces that survive). False when the projection does not tile (the placement is refused).
bool BoundStarDeviation(const EdgeStar& star, const Displacement* old_moved,
                        Displacement* new_moved, int* work);

}  // namespace femsimp
