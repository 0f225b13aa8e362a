// Polygons in mesh files (OBJ, OFF, PLY faces of more than three corners: quad-dominant
// exports of CAD systems and meshers), cut into triangles on reading, as a careful tool would,
// instead of refusing the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "engine/raw_mesh.h"

namespace femsimp {

// The most corners a face may have: a polygon is cut by choosing ears, which costs the square of
// its corners each time.
inline constexpr uint32_t kMaxPolygonCorners = 64;

// A face of the file with `corners` corners (4 to kMaxPolygonCorners), its number in the file.
struct PolygonFace {
  size_t face;
  uint32_t corners;
};

// mesh->triangles holds the file's faces in order, three corners each except the faces listed in
// `polygons` (in file order), whose corners stand in their place. Each polygon becomes
// corners - 2 triangles in the polygon's winding, cut at the ear whose smallest angle is largest
// first (in the plane of its Newell normal); its group, field values and line (face_lines, when
// not empty: one per face) go with every one of them. Refuses a corner that names no vertex of
// the file (by face, and line when known). `summary` receives one line for the user.
absl::Status TriangulatePolygons(const std::vector<PolygonFace>& polygons, RawMesh* mesh,
                                 std::vector<size_t>* face_lines, std::string* summary);

}  // namespace femsimp
