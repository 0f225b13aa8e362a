#include "engine/io/raw_importer.h"

namespace femsimp {

OpenMesh::VertexHandle RawImporter::add_vertex(const OpenMesh::Vec3f& p) {
  mesh_.positions.insert(mesh_.positions.end(), {p[0], p[1], p[2]});
  return OpenMesh::VertexHandle(static_cast<int>(mesh_.num_vertices() - 1));
}

OpenMesh::VertexHandle RawImporter::add_vertex(const OpenMesh::Vec3d& p) {
  return add_vertex(OpenMesh::Vec3f(p));
}

// Some readers (PLY) add the vertex first and set its point once the element is parsed.
OpenMesh::VertexHandle RawImporter::add_vertex() { return add_vertex(OpenMesh::Vec3f(0, 0, 0)); }

void RawImporter::set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& p) {
  const size_t v = static_cast<size_t>(vh.idx());
  if (vh.idx() < 0 || v >= mesh_.num_vertices()) return;
  for (int i = 0; i < 3; ++i) mesh_.positions[3 * v + i] = p[i];
}

OpenMesh::FaceHandle RawImporter::add_face(const VHandles& indices) {
  const size_t f = faces_seen_++;
  if (indices.size() != 3) {
    if (first_polygon_ == kNoFace) {
      first_polygon_ = f;
      first_polygon_size_ = indices.size();
    }
    return OpenMesh::FaceHandle(static_cast<int>(f));
  }
  for (const OpenMesh::VertexHandle& vh : indices) {
    // A negative index cannot be stored in the soup; an index past the end is kept for
    // Mesh::Build, which names it precisely.
    if (vh.idx() < 0 && first_bad_index_face_ == kNoFace) first_bad_index_face_ = f;
    mesh_.triangles.push_back(static_cast<uint32_t>(vh.idx()));
  }
  return OpenMesh::FaceHandle(static_cast<int>(f));
}

}  // namespace femsimp
