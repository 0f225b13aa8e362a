// Seam conformity of an assembly, judged from the two soups alone (no engine code): the
// output's non-manifold edges (seams) must be the input's simplified along themselves.
//   - every output seam point is an input seam point (same coordinates);
//   - every input seam point that is not an inner point of one seam curve (two seam edges with
//     the same face count: junctions, curve ends) is still a seam point of the output;
//   - the output's seams are exactly the input's with the seam points the output dropped left
//     out (a chain through dropped inner points becomes one edge), with the same face counts.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine/raw_mesh.h"

namespace femsimp::judge {

using SeamPoint = std::array<float, 3>;
using SeamEdges = std::map<std::pair<SeamPoint, SeamPoint>, uint32_t>;  // ends -> faces

// Non-manifold edges (used by 3+ faces, or twice in one direction) by their end points, each
// pair ordered, with their face counts.
SeamEdges SeamEdgesOf(const RawMesh& mesh);
std::set<SeamPoint> SeamPointsOf(const SeamEdges& seams);

// The seams `input` becomes when only the seam points in `kept` stay; *dropped_junctions counts
// the points left out that were not inner points of a seam curve.
SeamEdges SeamsSimplifiedTo(const SeamEdges& input, const std::set<SeamPoint>& kept,
                            size_t* dropped_junctions);

struct SeamConformity {
  size_t input_points = 0, output_points = 0;
  size_t input_seams = 0, output_seams = 0;
  std::vector<std::string> problems;  // empty: conforming
};
SeamConformity CheckSeamConformity(const RawMesh& input, const RawMesh& output);

}  // namespace femsimp::judge
