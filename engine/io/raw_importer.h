// An OpenMesh importer that records the raw vertex and face lists a reader produces. Loading
// into an OpenMesh mesh instead would silently drop non-manifold faces, which Mesh::Build must
// see to reject the input with a precise message.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/io/openmesh.h"
#include "engine/raw_mesh.h"

namespace femsimp {

class RawImporter : public OpenMesh::IO::BaseImporter {
 public:
  RawMesh& mesh() { return mesh_; }
  size_t faces_seen() const { return faces_seen_; }
  // The first face that is not a triangle (kNoFace if all are), and its vertex count.
  static constexpr size_t kNoFace = ~size_t{0};
  size_t first_polygon() const { return first_polygon_; }
  size_t first_polygon_size() const { return first_polygon_size_; }
  // The first face that references a vertex the reader never added.
  size_t first_bad_index_face() const { return first_bad_index_face_; }

  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override;
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override;
  OpenMesh::VertexHandle add_vertex() override;
  void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& p) override;
  OpenMesh::FaceHandle add_face(const VHandles& indices) override;
  size_t n_vertices() const override { return mesh_.num_vertices(); }
  size_t n_faces() const override { return faces_seen_; }
  size_t n_edges() const override { return 0; }

  // Everything below carries attributes femsimp does not use (normals, colours, texture
  // coordinates, status, connectivity of OpenMesh's own format): ignored.
  OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
    return OpenMesh::HalfedgeHandle();
  }
  OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override {
    return OpenMesh::FaceHandle();
  }
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                          const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                          const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(OpenMesh::FaceHandle, int) override {}
  void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
  void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  RawMesh mesh_;
  size_t faces_seen_ = 0;
  size_t first_polygon_ = kNoFace;
  size_t first_polygon_size_ = 0;
  size_t first_bad_index_face_ = kNoFace;
};

}  // namespace femsimp
