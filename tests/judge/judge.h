// Independent fidelity checks of a simplification (issue #5, docs/FIDELITY.md). Everything here
// is computed from the two triangle soups alone, with CGAL and plain geometry; nothing goes
// through the engine's mesh, flags or bounds, so the engine never judges itself.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp::judge {

using Vec3 = std::array<double, 3>;

double BoundingBoxDiagonal(const RawMesh& mesh);  // over all stored vertices

// The largest |coordinate| stored, times a few float epsilons: how far a vertex can be from
// where an exact computation put it just because RawMesh stores floats. Tests add it to
// tolerances the engine guarantees, since no float output can honour them more closely.
double FloatStorageSlack(const RawMesh& mesh);

// ---- Hausdorff distance ------------------------------------------------------------------------

// Two-sided Hausdorff distance between two surfaces by CGAL's bounded-error algorithm (Tang,
// Lee, Kim): each direction subdivides triangles of the first surface until the lower and upper
// bounds of its distance to the second surface are within `error` of each other, and returns the
// lower bound. Every figure is therefore a certified lower bound: true value in [d, d + error].
// A check "d <= tolerance" never fails a surface that keeps the tolerance, and lets through only
// surfaces that exceed it by less than `error`.
struct Hausdorff {
  double a_to_b = 0.0;  // sup over points of a of the distance to b
  double b_to_a = 0.0;
  double error = 0.0;
  double seconds = 0.0;
  double two_sided() const { return a_to_b > b_to_a ? a_to_b : b_to_a; }
};
Hausdorff HausdorffDistance(const RawMesh& a, const RawMesh& b, double error);

// The error tests use: 1 % of the tolerance (the smallest tolerance of issue #5 is 0.1 % of the
// bounding-box diagonal, so 1e-5 of it), which keeps a run on the test meshes around a second.
inline double HausdorffErrorFor(double tolerance) { return 0.01 * tolerance; }

// One direction by plain sampling, as CGAL's approximate_Hausdorff_distance does, but with a
// known covering: each face of `from` is cut into congruent triangles with sides at most
// `spacing`, and the distance of every corner to `to` is exact (CGAL's
// max_distance_to_triangle_mesh). Any point of a face is within spacing / sqrt(3) of a corner,
// so the result is a lower bound at most that far below the truth. Kept as a cross-check of
// HausdorffDistance: denser and slower for the same accuracy.
double SampledHausdorff(const RawMesh& from, const RawMesh& to, double spacing);

// Per face group: the two-sided distance between the faces of group g in a and in b. Groups
// present in only one mesh are reported with an infinite distance.
std::map<uint32_t, Hausdorff> GroupHausdorffDistances(const RawMesh& a, const RawMesh& b,
                                                      double error);

// ---- self-intersection, topology -------------------------------------------------------------

// True if two faces that do not share a vertex or an edge intersect, or two that share one
// intersect elsewhere. Non-manifold soups are split into manifold pieces first.
bool SelfIntersects(const RawMesh& mesh);
// How many pairs of faces intersect other than along a shared edge or vertex.
size_t SelfIntersectingPairs(const RawMesh& mesh);
// The same for the soup as it is (tests/judge/soup_intersections.cc): corners shared by index,
// so that the parts of an assembly touch at their seams instead of crossing there (the mesh
// test above splits a seam into copies that only touch). Degenerate faces are left out.
size_t SoupSelfIntersectingPairs(const RawMesh& mesh);
// Pairs of faces with no corner in common that lie in one plane and overlap there with a positive
// area (exact predicates and constructions): bodies exported apart that touch. Degenerate faces
// are left out.
size_t SoupOverlappingPairs(const RawMesh& mesh);

struct Topology {
  long vertices = 0, edges = 0, faces = 0;  // referenced vertices only
  long boundary_edges = 0;                  // used by one face
  long nonmanifold_edges = 0;               // used by more than two faces
  long nonmanifold_vertices = 0;            // faces around it form more than one fan
  long misoriented_edges = 0;               // two faces traverse it in the same direction
  long components = 0;                      // connected through shared vertices
  long boundary_loops = 0;
  long euler() const { return vertices - edges + faces; }
  bool manifold() const {
    return nonmanifold_edges == 0 && nonmanifold_vertices == 0 && misoriented_edges == 0;
  }
  bool closed_manifold() const { return manifold() && boundary_edges == 0; }
  // Summed over components, from chi = 2c - 2g - b; meaningful for oriented manifolds only.
  long genus() const { return (2 * components - euler() - boundary_loops) / 2; }
};
Topology ComputeTopology(const RawMesh& mesh);

// ---- integral properties -----------------------------------------------------------------------

struct Solid {
  double volume = 0.0;  // signed: positive for a closed surface oriented outwards
  Vec3 centroid{};      // of the enclosed solid (uniform density)
};
// Divergence theorem over the faces: meaningful for closed surfaces only.
Solid SolidProperties(const RawMesh& mesh);

struct Surface {
  double area = 0.0;
  Vec3 centroid{};  // area-weighted
};
Surface SurfaceProperties(const RawMesh& mesh);

// Resultant of a face field read as a pressure on each face: sum of p * area * normal (normal
// from the counter-clockwise order), per face group (all faces in group 0 when the mesh has no
// groups), and the group's total absolute load sum |p| * area.
struct GroupLoad {
  Vec3 force{};
  double abs_load = 0.0;
  double area = 0.0;
  size_t faces = 0;
};
std::map<uint32_t, GroupLoad> FieldResultants(const RawMesh& mesh, size_t field);

// |force_b - force_a| / abs_load_a for every group of a (infinite for a group missing in b, or
// for an unloaded group that gained a load):
// the relative resultant change that SimplifyOptions::max_field_change bounds.
std::map<uint32_t, double> RelativeResultantChange(const std::map<uint32_t, GroupLoad>& a,
                                                   const std::map<uint32_t, GroupLoad>& b);

// ---- feature lines -----------------------------------------------------------------------------

struct Segment {
  Vec3 a, b;
};

// Feature edges found from the geometry alone: boundary edges, edges used by more than two
// faces, edges between faces of different groups, and edges whose dihedral angle (between the
// two face normals) exceeds angle_deg.
struct FeatureEdges {
  std::vector<Segment> segments;
  size_t boundary = 0, nonmanifold = 0, group_border = 0, sharp = 0;  // a border may be sharp too
};
FeatureEdges ExtractFeatureEdges(const RawMesh& mesh, double angle_deg);

// How well the feature lines of `original` are represented by those of `simplified` (each
// extracted with ExtractFeatureEdges at angle_deg). Points are sampled along every original
// feature edge at most `spacing` apart (end points included); the distance of each to the
// nearest simplified feature edge is exact (CGAL AABB tree), and a point of an edge is at most
// spacing / 2 from a sample, so the true maximum lies in [max_distance, max_distance + error].
struct FeatureCoverage {
  size_t original_edges = 0, simplified_edges = 0;
  size_t samples = 0;
  double max_distance = 0.0;  // from an original feature point to the simplified feature lines
  Vec3 worst_point{};
  // The other way round (simplified feature points to original lines): reported, since a
  // simplification may make new creases, but not bounded by the engine's options.
  double reverse_max_distance = 0.0;
  double error = 0.0;
};
// The simplified mesh's feature edges are detected at simplified_angle_deg (negative: the same
// angle): a soft crease just above the angle may come out of the simplification, still in
// place, a little softer.
FeatureCoverage CheckFeatureCoverage(const RawMesh& original, const RawMesh& simplified,
                                     double angle_deg, double spacing,
                                     double simplified_angle_deg = -1.0);

// ---- face groups -------------------------------------------------------------------------------

// Group ids used by the faces (empty when the mesh has no groups).
std::vector<uint32_t> GroupIds(const RawMesh& mesh);

}  // namespace femsimp::judge
