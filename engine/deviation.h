// The guaranteed deviation bound of a half-edge collapse (docs/FIDELITY.md).
//
// Every live face f carries e_f: there is a continuous map phi from the input surface onto the
// current one with |phi(p) - p| <= e_f wherever phi(p) lies on f. Such a map bounds the
// two-sided Hausdorff distance by max e_f. A collapse V -> Vd replaces V's fan (the old patch)
// by Vd's new faces (the new patch) inside the same link polygon; BoundDeviation builds the next
// map there: both patches are laid out in one plane (the old one with V moved to V', its
// closest point on the feature line when V slides along one), points with the same plane
// position correspond, and the displacement, affine on every cell of the overlay of the two
// layouts, is largest at a cell corner: V', a crossing of an old and a new spoke, or a link
// vertex (which does not move). The new bound of a face is the largest old bound it overlaps
// plus the largest corner displacement on it. Local to the one-ring, so it runs in parallel.
#pragma once

#include "engine/ring.h"
#include "engine/star.h"

namespace femsimp {

// old_error[f]: bound of fan face f. On success fills new_error[f] for every fan face that
// survives (the two containing V - Vd are deleted) and returns true; returns false when the
// layouts do not tile the link polygon (the map cannot be built: the collapse is refused).
// line_other: index of V's other feature neighbour when V slides along a feature line, or -1.
// *work counts the elementary tests (the cell back end's cycle model).
bool BoundDeviation(const Ring& ring, int target, int line_other, const float* old_error,
                    float* new_error, int* work);

// The same for a full-edge collapse (engine/star.h): both patches are projected onto the plane
// perpendicular to the old star's area-weighted normal, where each must tile the link polygon
// (every triangle counter-clockwise, the angles around V, Vd and P each a full turn), points
// with the same projection correspond, and the displacement, affine on every cell of the
// overlay, is largest at a cell corner: a corner of either triangle inside the other, or a
// crossing of their edges. old_error / new_error are indexed by star face (new_error for the
// faces that survive). False when the projection does not tile (the placement is refused).
bool BoundStarDeviation(const EdgeStar& star, const float* old_error, float* new_error, int* work);

}  // namespace femsimp
