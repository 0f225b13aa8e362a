#include "engine/plane_fill.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <exception>

#include "absl/strings/str_cat.h"

namespace femsimp {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int depth = -1;  // loops around the face (-1: not reached yet)
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact predicates, and constraints allowed to cross: a crossing then shows as a point added,
// which is how a loop that is not simple is told apart.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

std::array<double, 3> Cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::array<double, 3> Unit(const std::array<double, 3>& a) {
  const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  return {a[0] / l, a[1] / l, a[2] / l};
}

}  // namespace

std::array<double, 3> NewellNormal(const std::array<double, 3>* corners, size_t n) {
  std::array<double, 3> normal{};
  for (size_t i = 0; i < n; ++i) {
    const std::array<double, 3>& a = corners[i];
    const std::array<double, 3>& b = corners[(i + 1) % n];
    normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
    normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
    normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  return normal;
}

namespace {

absl::StatusOr<std::vector<std::array<uint32_t, 3>>> Triangulate(
    const std::vector<std::vector<std::array<double, 3>>>& loops,
    const std::array<double, 3>& normal) {
  if (!(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2] > 0))
    return absl::InvalidArgumentError("the plane's normal is zero");
  // An orthonormal frame of the plane: distances and angles in it are those of the part.
  const std::array<double, 3> n = Unit(normal);
  const int least = std::fabs(n[0]) <= std::fabs(n[1]) && std::fabs(n[0]) <= std::fabs(n[2]) ? 0
                    : std::fabs(n[1]) <= std::fabs(n[2])                                     ? 1
                                                                                             : 2;
  std::array<double, 3> axis{};
  axis[least] = 1;
  const std::array<double, 3> u = Unit(Cross(n, axis)), v = Cross(n, u);

  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handle;
  std::array<double, 3> origin{};
  for (const auto& loop : loops) {
    if (loop.size() < 3)
      return absl::InvalidArgumentError(
          absl::StrCat("a loop of ", loop.size(), " corners bounds no region"));
    if (handle.empty()) origin = loop[0];
    for (const auto& p : loop) {
      const double d[3] = {p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]};
      const size_t before = cdt.number_of_vertices();
      const Cdt::Vertex_handle h = cdt.insert(K::Point_2(d[0] * u[0] + d[1] * u[1] + d[2] * u[2],
                                                         d[0] * v[0] + d[1] * v[1] + d[2] * v[2]));
      if (cdt.number_of_vertices() == before)
        return absl::InvalidArgumentError(
            absl::StrCat("corners ", h->info(), " and ", handle.size(), " lie at one point"));
      h->info() = static_cast<uint32_t>(handle.size());
      handle.push_back(h);
    }
  }
  size_t first = 0;
  for (const auto& loop : loops) {
    for (size_t i = 0; i < loop.size(); ++i)
      cdt.insert_constraint(handle[first + i], handle[first + (i + 1) % loop.size()]);
    first += loop.size();
  }
  if (cdt.number_of_vertices() != handle.size())
    return absl::InvalidArgumentError("edges of the loops cross each other in their plane");
  first = 0;
  for (const auto& loop : loops) {
    for (size_t i = 0; i < loop.size(); ++i)
      if (!cdt.is_edge(handle[first + i], handle[first + (i + 1) % loop.size()]))
        return absl::InvalidArgumentError(
            absl::StrCat("corner ", first + i, "'s edge runs through another corner"));
    first += loop.size();
  }

  // Depth by a walk out from the infinite faces, one more across each loop edge.
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().depth = -1;
  std::vector<Cdt::Face_handle> seeds = {cdt.infinite_face()}, next, stack;
  for (int depth = 0; !seeds.empty(); ++depth) {
    for (const Cdt::Face_handle& s : seeds)
      if (s->info().depth < 0) {
        s->info().depth = depth;
        stack.push_back(s);
      }
    while (!stack.empty()) {
      const Cdt::Face_handle f = stack.back();
      stack.pop_back();
      for (int e = 0; e < 3; ++e) {
        const Cdt::Face_handle g = f->neighbor(e);
        if (g->info().depth >= 0) continue;
        if (cdt.is_constrained({f, e})) {
          next.push_back(g);
        } else {
          g->info().depth = depth;
          stack.push_back(g);
        }
      }
    }
    seeds.swap(next);
    next.clear();
  }
  std::vector<std::array<uint32_t, 3>> triangles;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info().depth % 2 == 0) continue;
    std::array<uint32_t, 3> t;
    for (int c = 0; c < 3; ++c) t[c] = f->vertex(c)->info();
    triangles.push_back(t);
  }
  if (triangles.empty()) return absl::InvalidArgumentError("the loops bound no region");
  return triangles;
}

}  // namespace

absl::StatusOr<std::vector<std::array<uint32_t, 3>>> FillPlaneRegion(
    const std::vector<std::vector<std::array<double, 3>>>& loops,
    const std::array<double, 3>& normal) {
  try {  // CGAL reports a violated precondition by an exception
    return Triangulate(loops, normal);
  } catch (const std::exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("the triangulation failed: ", e.what()));
  }
}

}  // namespace femsimp
