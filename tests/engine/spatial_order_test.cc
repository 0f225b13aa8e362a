// SortSpatially renumbers, and changes nothing else: the same triangles (as places), with the
// same groups, fields and locked places, in curve order.
#include "engine/spatial_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <tuple>
#include <vector>

#include "engine/mesh.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using Place = std::array<float, 3>;
// A triangle by its corners' places from its smallest corner on (a rotation keeps its
// orientation), with its group and field value.
using PlacedFace = std::tuple<std::array<Place, 3>, uint32_t, float>;

Place At(const RawMesh& m, uint32_t v) {
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

std::vector<PlacedFace> PlacedFaces(const RawMesh& m) {
  std::vector<PlacedFace> faces;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    std::array<Place, 3> c = {At(m, m.triangles[3 * f]), At(m, m.triangles[3 * f + 1]),
                              At(m, m.triangles[3 * f + 2])};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    faces.emplace_back(c, m.face_groups.empty() ? 0 : m.face_groups[f],
                       m.face_fields.empty() ? 0.0f : m.face_fields[0].values[f]);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// The torus's vertices and faces shuffled, with a group and a field per face and a few locked
// vertices: an input in no spatial order.
RawMesh ShuffledTorus() {
  RawMesh m = testing::MakeTorus(24, 12);
  std::mt19937 rng(7);
  std::vector<uint32_t> perm(m.num_vertices());
  for (uint32_t i = 0; i < perm.size(); ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), rng);
  RawMesh s = m;
  for (uint32_t v = 0; v < perm.size(); ++v)
    for (int a = 0; a < 3; ++a) s.positions[3 * perm[v] + a] = m.positions[3 * v + a];
  for (uint32_t& i : s.triangles) i = perm[i];
  s.face_groups.resize(s.num_faces());
  s.face_fields.push_back({"p", std::vector<float>(s.num_faces())});
  for (size_t f = 0; f < s.num_faces(); ++f) {
    s.face_groups[f] = static_cast<uint32_t>(f % 5);
    s.face_fields[0].values[f] = static_cast<float>(f) * 0.5f;
  }
  s.locked_vertices = {perm[0], perm[17], perm[100]};
  std::sort(s.locked_vertices.begin(), s.locked_vertices.end());
  return s;
}

TEST(SpatialOrder, RenumbersOnly) {
  const RawMesh before = ShuffledTorus();
  RawMesh after = before;
  const std::vector<uint32_t> new_id = SortSpatially(after);
  ASSERT_EQ(new_id.size(), before.num_vertices());
  ASSERT_EQ(after.num_vertices(), before.num_vertices());
  ASSERT_EQ(after.num_faces(), before.num_faces());
  for (uint32_t v = 0; v < before.num_vertices(); ++v)
    EXPECT_EQ(At(after, new_id[v]), At(before, v));
  EXPECT_EQ(PlacedFaces(after), PlacedFaces(before));
  std::vector<Place> locked_before, locked_after;
  for (uint32_t v : before.locked_vertices) locked_before.push_back(At(before, v));
  for (uint32_t v : after.locked_vertices) locked_after.push_back(At(after, v));
  std::sort(locked_before.begin(), locked_before.end());
  std::sort(locked_after.begin(), locked_after.end());
  EXPECT_EQ(locked_after, locked_before);
  EXPECT_TRUE(std::is_sorted(after.locked_vertices.begin(), after.locked_vertices.end()));
  // Still a valid closed mesh.
  EXPECT_TRUE(Mesh::Build(after).ok());
}

// Neighbours in the mesh become neighbours in memory: the mean id distance along an edge falls
// far below the shuffled input's (about a third of the vertex count).
TEST(SpatialOrder, EdgesJoinNearbyIds) {
  const auto mean_edge_span = [](const RawMesh& m) {
    double sum = 0.0;
    for (size_t f = 0; f < m.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const double a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
        sum += std::abs(a - b);
      }
    return sum / (3.0 * m.num_faces());
  };
  RawMesh m = ShuffledTorus();
  const double shuffled = mean_edge_span(m);
  SortSpatially(m);
  EXPECT_LT(mean_edge_span(m), shuffled / 4) << shuffled;
}

TEST(SpatialOrder, SameSoupSameOrder) {
  RawMesh a = ShuffledTorus(), b = ShuffledTorus();
  SortSpatially(a);
  SortSpatially(b);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
}

// What the checks after it must refuse by the input's own ids is left alone.
TEST(SpatialOrder, LeavesAMalformedSoupAsItIs) {
  RawMesh out_of_range = testing::Tetrahedron();
  out_of_range.triangles[4] = 99;
  RawMesh copy = out_of_range;
  EXPECT_TRUE(SortSpatially(copy).empty());
  EXPECT_EQ(copy.triangles, out_of_range.triangles);

  RawMesh short_groups = testing::Tetrahedron();
  short_groups.face_groups = {1, 2};
  copy = short_groups;
  EXPECT_TRUE(SortSpatially(copy).empty());
  EXPECT_EQ(copy.positions, short_groups.positions);

  RawMesh empty;
  EXPECT_TRUE(SortSpatially(empty).empty());
}

}  // namespace
}  // namespace femsimp
