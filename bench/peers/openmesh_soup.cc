#include "bench/peers/openmesh_soup.h"

#include <vector>

namespace femsimp::bench {

void ToTriMesh(const RawMesh& in, TriMesh& mesh) {
  std::vector<TriMesh::VertexHandle> vh;
  vh.reserve(in.num_vertices());
  for (size_t v = 0; v < in.num_vertices(); ++v)
    vh.push_back(mesh.add_vertex(
        TriMesh::Point(in.positions[3 * v], in.positions[3 * v + 1], in.positions[3 * v + 2])));
  for (size_t f = 0; f < in.num_faces(); ++f)
    mesh.add_face(vh[in.triangles[3 * f]], vh[in.triangles[3 * f + 1]],
                  vh[in.triangles[3 * f + 2]]);
  mesh.request_face_normals();
  mesh.update_face_normals();
}

RawMesh FromTriMesh(const TriMesh& mesh) {
  RawMesh out;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
  }
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) out.triangles.push_back(static_cast<uint32_t>(v.idx()));
  return out;
}

}  // namespace femsimp::bench
