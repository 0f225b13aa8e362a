// A femsimp soup as an OpenMesh triangle mesh, for the benchmarks that run OpenMesh beside
// femsimp on the same mesh (faces OpenMesh refuses, e.g. at a non-manifold edge, are left out).
#pragma once

#include <vector>

#include "engine/io/openmesh.h"
#include "engine/raw_mesh.h"

namespace femsimp::bench {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

inline TriMesh ToOpenMesh(const RawMesh& raw) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  vh.reserve(raw.num_vertices());
  for (size_t v = 0; v < raw.num_vertices(); ++v)
    vh.push_back(mesh.add_vertex(
        TriMesh::Point(raw.positions[3 * v], raw.positions[3 * v + 1], raw.positions[3 * v + 2])));
  for (size_t f = 0; f < raw.num_faces(); ++f)
    mesh.add_face(vh[raw.triangles[3 * f]], vh[raw.triangles[3 * f + 1]],
                  vh[raw.triangles[3 * f + 2]]);
  return mesh;
}

}  // namespace femsimp::bench
