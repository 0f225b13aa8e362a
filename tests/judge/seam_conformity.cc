#include "tests/judge/seam_conformity.h"

#include <algorithm>
#include <cstdio>

namespace femsimp::judge {
namespace {

SeamPoint PointAt(const RawMesh& m, uint32_t v) {
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

std::string Text(const SeamPoint& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", p[0], p[1], p[2]);
  return buf;
}

}  // namespace

SeamEdges SeamEdgesOf(const RawMesh& mesh) {
  // Directed uses per undirected edge: a manifold edge has one each way.
  std::map<std::pair<uint32_t, uint32_t>, std::pair<uint32_t, uint32_t>> uses;
  for (size_t f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.triangles[3 * f + k], b = mesh.triangles[3 * f + (k + 1) % 3];
      auto& u = uses[std::minmax(a, b)];
      (a < b ? u.first : u.second) += 1;
    }
  SeamEdges out;
  for (const auto& [edge, u] : uses)
    if (u.first + u.second >= 3 || u.first >= 2 || u.second >= 2)
      out[std::minmax(PointAt(mesh, edge.first), PointAt(mesh, edge.second))] = u.first + u.second;
  return out;
}

std::set<SeamPoint> SeamPointsOf(const SeamEdges& seams) {
  std::set<SeamPoint> out;
  for (const auto& [ends, faces] : seams) {
    out.insert(ends.first);
    out.insert(ends.second);
  }
  return out;
}

SeamEdges SeamsSimplifiedTo(const SeamEdges& input, const std::set<SeamPoint>& kept,
                            size_t* dropped_junctions) {
  std::map<SeamPoint, std::vector<std::pair<SeamPoint, uint32_t>>> at;  // (other end, faces)
  for (const auto& [ends, faces] : input) {
    at[ends.first].emplace_back(ends.second, faces);
    at[ends.second].emplace_back(ends.first, faces);
  }
  const auto inner = [&](const SeamPoint& p) {
    const auto& e = at[p];
    return e.size() == 2 && e[0].second == e[1].second;
  };
  *dropped_junctions = 0;
  for (const auto& [p, edges] : at) *dropped_junctions += !kept.count(p) && !inner(p);
  SeamEdges out;
  for (const auto& [p, edges] : at) {
    if (!kept.count(p)) continue;
    for (auto [q, faces] : edges) {
      SeamPoint prev = p;
      for (size_t steps = 0; !kept.count(q) && inner(q) && steps <= input.size(); ++steps) {
        const SeamPoint next = at[q][0].first == prev ? at[q][1].first : at[q][0].first;
        prev = q;
        q = next;
      }
      if (kept.count(q)) out[std::minmax(p, q)] = faces;
    }
  }
  return out;
}

SeamConformity CheckSeamConformity(const RawMesh& input, const RawMesh& output) {
  SeamConformity c;
  const SeamEdges in = SeamEdgesOf(input), out = SeamEdgesOf(output);
  const std::set<SeamPoint> in_points = SeamPointsOf(in), out_points = SeamPointsOf(out);
  c.input_points = in_points.size();
  c.output_points = out_points.size();
  c.input_seams = in.size();
  c.output_seams = out.size();
  size_t foreign = 0;
  for (const SeamPoint& p : out_points)
    if (!in_points.count(p) && foreign++ == 0)
      c.problems.push_back("output seam point " + Text(p) + " is not an input seam point");
  size_t dropped = 0;
  const SeamEdges expected = SeamsSimplifiedTo(in, out_points, &dropped);
  if (dropped > 0)
    c.problems.push_back(std::to_string(dropped) +
                         " seam junctions or curve ends of the input are not seam points of "
                         "the output");
  size_t differ = 0;
  std::string first;
  for (const auto& [ends, faces] : expected) {
    const auto it = out.find(ends);
    if (it == out.end() || it->second != faces) {
      if (differ++ == 0)
        first = "seam " + Text(ends.first) + "-" + Text(ends.second) + " expected with " +
                std::to_string(faces) + " faces, found " +
                (it == out.end() ? std::string("none") : std::to_string(it->second));
    }
  }
  for (const auto& [ends, faces] : out)
    if (!expected.count(ends) && differ++ == 0)
      first = "seam " + Text(ends.first) + "-" + Text(ends.second) + " is not the input's";
  if (differ > 0)
    c.problems.push_back(std::to_string(differ) + " seams differ from the input's simplified " +
                         "along themselves (first: " + first + ")");
  return c;
}

}  // namespace femsimp::judge
