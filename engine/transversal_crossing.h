// Whether two triangles certainly cross: an edge of one passes through the inside of the other,
// with every orientation test behind that verdict certain in floating point (its value beyond
// the rounding error it can carry). This is the test for a report to an analyst, where a false
// alarm costs trust; the self-intersection rule uses the conservative test of
// engine/triangle_intersection.h instead, where a false alarm only refuses a collapse.
//
// What it leaves out, by design: contacts (a corner on the other face, edges that meet, shared
// corners and edges), pairs whose verdict is within rounding of touching, and faces overlapping
// within one plane (a fold). Two triangles that are not coplanar and meet beyond their contacts
// have an edge of one through the inside of the other, so every other crossing is found.
#pragma once

#include <optional>

#include "engine/triangle_intersection.h"

namespace femsimp {

// A point where they cross (where the first edge found pierces the other face), or none.
std::optional<DVec3> TransversalCrossing(const Triangle& a, const Triangle& b);

}  // namespace femsimp
