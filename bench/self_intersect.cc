#include "bench/self_intersect.h"

#include <array>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

namespace femsimp::bench {

bool DoesSelfIntersect(const RawMesh& mesh) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<K::Point_3> points;
  points.reserve(mesh.num_vertices());
  for (size_t v = 0; v < mesh.num_vertices(); ++v)
    points.emplace_back(mesh.positions[3 * v], mesh.positions[3 * v + 1],
                        mesh.positions[3 * v + 2]);
  std::vector<std::array<size_t, 3>> faces(mesh.num_faces());
  for (size_t f = 0; f < faces.size(); ++f)
    faces[f] = {mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]};
  // Duplicates non-manifold vertices so that any soup becomes a polygon mesh.
  PMP::orient_polygon_soup(points, faces);
  CGAL::Surface_mesh<K::Point_3> sm;
  PMP::polygon_soup_to_polygon_mesh(points, faces, sm);
  return PMP::does_self_intersect(sm);
}

}  // namespace femsimp::bench
