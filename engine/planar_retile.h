// A collapse inside a flat face of a CAD part, proved to re-tile the region its fan covers.
//
// Most of a CAD part's collapses happen inside its flat faces, and most of those faces lie on
// the axis planes of the part's coordinates, where every corner has the same coordinate exactly
// (75 % of the self-intersection checks of knob_fine's plain call, 81 % of bracket_fine's).
// There the new triangles of a collapse cover exactly the polygon the old fan covers, so they
// can meet another triangle only where the old ones already did: the self-intersection rule
// (engine/rules/self_intersection.cc) needs no test against the faces nearby.
#pragma once

#include "engine/ring.h"

namespace femsimp {

// Whether collapsing V onto fan.nbr[target] re-tiles exactly the polygon V's fan covers: V and
// its whole one-ring lie in one plane x_a = c (the same float in coordinate a), the fan is
// closed and winds once around V, and every old triangle (V, nbr[f], nbr[f + 1]) and every new
// one (Vd, nbr[f], nbr[f + 1]) is of one orientation in that plane, certainly in floating point
// (beyond Shewchuk's error bound for the 2D orientation). The ring is then a simple polygon
// star-shaped around V, and the new triangles cover each point inside it once and no point
// outside (the winding number of the ring around a point is their count there): they meet
// each other only along their shared edges and at Vd, and a face outside the fan only where it
// meets the polygon, that is, where it met an old triangle. False also means "not shown".
// *tests (when given) counts the coordinate compares and orientation tests made (the cell back
// end's cycle model).
bool RetilesTheFanInItsPlane(const Ring& fan, int target, int* tests = nullptr);

}  // namespace femsimp
