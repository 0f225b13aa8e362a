// Indexed triangle soup: the exchange format between file I/O, the wire format and the engine.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace femsimp {

struct RawMesh {
  std::vector<float> positions;       // x, y, z per vertex
  std::vector<uint32_t> triangles;    // three vertex indices per face, counter-clockwise
  std::vector<uint32_t> face_groups;  // empty, or one group id per face

  size_t num_vertices() const { return positions.size() / 3; }
  size_t num_faces() const { return triangles.size() / 3; }
};

}  // namespace femsimp
