// Meshes for the tests, written once: small hand-made ones, generated ones, the files of
// tests/data, and geometry helpers to check results with.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>

#include "engine/mesh.h"
#include "engine/raw_mesh.h"
#include "engine/ring.h"
#include "engine/simplify.h"
#include "engine/vec.h"

namespace femsimp::testing {

// A closed fan around vertex 0 with neighbours 1..n on the unit regular polygon at z = 0, the
// centre at height apex (fan face i's first half-edge is 3i): for the rules' unit tests.
Ring RegularFan(int n, float apex = 0.0f);
RawMesh FlatGrid(int n);  // (n+1)^2 vertices on the unit square, open boundary
RawMesh Tetrahedron();    // unit corner tetrahedron, closed
RawMesh Octahedron();
RawMesh SingleTriangle();

// A closed tetrahedron, counter-clockwise seen from outside, with coordinates that need all
// nine significant digits of a float (for file round trips).
RawMesh PreciseTetrahedron();

// Closed box [0, size[0]] x [0, size[1]] x [0, size[2]], each side split into cells[a] x cells[b]
// squares of two triangles, counter-clockwise seen from outside (a beam or a plate for the FE
// check's known answers).
RawMesh MakeBox(const std::array<double, 3>& size, const std::array<int, 3>& cells);
// `add`'s vertices and faces appended to `m` (a second body in one soup), moved by `shift`.
void Append(RawMesh& m, const RawMesh& add, const std::array<float, 3>& shift);
// `m` turned about the origin by 0.61 rad about the skew axis (1, 0.7, 0.3) and stored in floats,
// as a CAD export of a tilted part is: planes that were exact are so only up to that rounding.
RawMesh TurnedSkew(RawMesh m);

// `facets` triangles with corners of their own, each within `size` of a point drawn in the
// unit cube (size 1: anywhere in it), from a fixed generator seeded with `seed`: a soup whose
// facets cross each other everywhere.
RawMesh RandomSoup(uint32_t facets, uint32_t seed, float size = 1.0f);

// Closed torus of n * m vertices and 2nm faces (a valid closed 2-manifold), radii R and r.
RawMesh MakeTorus(int n, int m, double R = 3.0, double r = 1.0);

// Walls of two thicknesses in one closed mesh, for the wall rule: a torus shell 0.1 thick (tube
// radii 1 and 0.9 around a ring of radius 3, centred at the origin) beside a solid torus (tube
// radius 1, 2 across) centred at x = 10, 96 x 40 vertices each, facing out of the solid; face
// group 1 for the shell, 2 for the solid torus.
RawMesh ShellBesideSolidTorus();

// The unit cube (vertex i at (i & 1, i >> 1 & 1, i >> 2 & 1), facets 0-9 its five lower sides as
// two triangles each) with its top split into a fan around (0.7, 0.3, 1) (vertex 8), whose two
// facets on edge 5-8 are replaced by the other diagonal 4-7 of their quad: facets 10 = (4, 5, 7)
// and 11 = (7, 8, 4), the second turned over onto the first (8 lies inside triangle 4-5-7), as
// a tessellator that took the wrong diagonal writes it; 12 = (7, 6, 8), 13 = (6, 4, 8). Facet
// 11 lies on all three of its neighbours (three folded edges); flipping 4-7 back to 5-8
// unfolds it.
RawMesh CubeWithAFoldOnTop();

// A torus (MakeTorus(n, m)) as a careless export writes it, for the repair stage end to end:
// facets 3 and 10 flipped; a crack: the faces of the last ring (i = n - 1) use their own copies
// of ring 0's m vertices (same coordinates, appended); then a copy of facet 0 (a duplicate) and a
// facet that repeats a vertex (degenerate) appended. Repair gives back MakeTorus(n, m)'s surface:
// BrokenTorusRepairsOf(m) lists the changes per kind.
RawMesh BrokenTorus(int n, int m);
struct BrokenTorusRepairs {
  size_t flipped = 2, duplicate = 1, degenerate = 1;
  size_t welded, stitched;  // m each
};
BrokenTorusRepairs BrokenTorusRepairsOf(int m);

// Adds four face groups (ids 10..13, consecutive runs of faces: bands of a torus) and two face
// fields constant per group, "pressure" = 1000 + group and "heat_flux" = -group / 2, so that
// every surviving face of a simplified mesh can be checked against its group.
RawMesh WithGroupsAndFields(RawMesh mesh);
// Checks that every face of `out` has one of those groups and its group's field values; returns
// the distinct groups seen (0 after a failed check).
size_t ExpectGroupsAndFields(const RawMesh& out);

std::string TestDataPath(const std::string& name);  // in tests/data
RawMesh LoadTestMesh(const std::string& name);      // from tests/data, fails the test if missing

// One engine run, failing the test on any error: builds `input`, simplifies it, checks the
// half-edge invariants, and keeps the input, the output soup and the result.
struct SimplifyRun {
  RawMesh input, output;
  SimplifyResult result;
};
SimplifyRun SimplifyChecked(const RawMesh& input, const SimplifyOptions& options);
SimplifyRun SimplifyCheckedWith(const RawMesh& input, const SimplifyOptions& options,
                                const SimplifyControl& control);

// A SimplifyControl::cancelled that says true once a vertex of `mesh` is gone, so that the
// cancel lands inside the first pass's removals, past the set-up (which polls too).
std::function<bool()> CancelOnceRemoving(const Mesh& mesh);

// Smallest interior angle (degrees) of a triangle of the soup.
double MinAngleDegrees(const RawMesh& mesh, size_t face);

// Volume the soup's triangles enclose, signed (positive when they face outward).
double SignedVolume(const RawMesh& mesh);

// Distance from p to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
double PointTriangleDistance(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c);

}  // namespace femsimp::testing
