#include "engine/imprint.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/crossings.h"
#include "engine/prepare.h"
#include "engine/repair.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using testing::Append;
using testing::MakeBox;

// A plate 10 x 10 x 1 (a 5 x 5 grid on top) and a block 4 x 4 x 2 standing on it at (x, y), its
// bottom a 3 x 3 grid: two bodies exported apart, their contact triangulated twice.
RawMesh BlockOnPlate(float x, float y, float lift = 0) {
  RawMesh soup = MakeBox({10, 10, 1}, {5, 5, 1});
  Append(soup, MakeBox({4, 4, 2}, {3, 3, 2}), {x, y, 1 + lift});
  return soup;
}

RepairOptions Imprinting() {
  RepairOptions options;
  options.imprint = true;
  return options;
}

struct Parts {
  std::vector<double> input, output;  // ascending
  RawMesh out;
};

Parts SimplifyAndMeasure(const RawMesh& soup) {
  Parts parts;
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(soup, Imprinting());
  EXPECT_TRUE(prepared.ok()) << prepared.status();
  if (!prepared.ok()) return parts;
  absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, SimplifyOptions{});
  EXPECT_TRUE(result.ok()) << result.status();
  absl::StatusOr<RawMesh> out =
      OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
  EXPECT_TRUE(out.ok()) << out.status();
  if (!result.ok() || !out.ok()) return parts;
  for (const SimplifyResult::PartVolume& p : result->parts) {
    parts.input.push_back(p.input);
    parts.output.push_back(p.output);
  }
  std::sort(parts.input.begin(), parts.input.end());
  std::sort(parts.output.begin(), parts.output.end());
  parts.out = *std::move(out);
  return parts;
}

// The block's footprint, crossed by the plate's grid lines, becomes one surface shared by both:
// nothing overlaps any more, the footprint's rim is a seam, and the two are solids of their own
// volumes (the shared facets count for both).
TEST(Imprint, BlockOnPlateSharesItsFootprint) {
  RawMesh apart = BlockOnPlate(3.2f, 2.9f);
  ASSERT_TRUE(RepairMesh(apart, RepairOptions{}).ok());
  ASSERT_GT(FindCrossings(apart).overlaps.pairs, 0u);

  RawMesh mesh = apart;
  const ImprintResult imprint = ImprintContacts(mesh);
  ASSERT_EQ(imprint.contacts.size(), 1u);
  EXPECT_TRUE(imprint.left.empty());
  const ImprintedContact& contact = imprint.contacts[0];
  EXPECT_NEAR(contact.area, 16.0, 1e-4);
  EXPECT_NEAR(contact.at[0], 5.2, 1e-4);
  EXPECT_NEAR(contact.at[1], 4.9, 1e-4);
  EXPECT_NEAR(contact.at[2], 1.0, 1e-6);
  EXPECT_GT(contact.points_added, 0u);      // where the grids cross
  EXPECT_GT(imprint.neighbours_split, 0u);  // the block's sides at the footprint's rim
  const SoupCrossings after = FindCrossings(mesh);
  EXPECT_EQ(after.overlaps.pairs, 0u);
  EXPECT_EQ(after.pairs, 0u);
  ASSERT_EQ(imprint.facet_origin.size(), mesh.num_faces());
  ASSERT_EQ(imprint.vertex_origin.size(), mesh.num_vertices());

  // Through the repair: counted, checked, and its seams listed.
  RawMesh repaired = BlockOnPlate(3.2f, 2.9f);
  absl::StatusOr<RepairResult> r = RepairMesh(repaired, Imprinting());
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kImprintedContact), 1u) << r->report.Details();
  EXPECT_EQ(r->report.count(RepairKind::kContactLeft), 0u);
  EXPECT_GT(r->seams.size(), 0u);
  EXPECT_EQ(r->report.count(RepairKind::kSeamEdge), r->seams.size());
  EXPECT_EQ(FindCrossings(repaired).overlaps.pairs, 0u);
  EXPECT_NE(r->report.Summary().find("imprinted 1 contact of bodies exported apart"),
            std::string::npos)
      << r->report.Summary();

  const Parts parts = SimplifyAndMeasure(BlockOnPlate(3.2f, 2.9f));
  ASSERT_EQ(parts.input.size(), 2u);
  EXPECT_NEAR(parts.input[0], 32.0, 1e-4);
  EXPECT_NEAR(parts.input[1], 100.0, 1e-4);
  for (size_t k = 0; k < 2; ++k)
    EXPECT_LE(std::fabs(parts.output[k] / parts.input[k] - 1), 0.005 + 1e-9);
  EXPECT_EQ(FindCrossings(parts.out).overlaps.pairs, 0u);
  EXPECT_EQ(FindCrossings(parts.out).pairs, 0u);
}

// Without the option nothing changes: the contact stays as exported.
TEST(Imprint, OffByDefault) {
  RawMesh mesh = BlockOnPlate(3.2f, 2.9f);
  absl::StatusOr<RepairResult> r = RepairMesh(mesh, RepairOptions{});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->report.count(RepairKind::kImprintedContact), 0u);
  EXPECT_TRUE(r->seams.empty());
  EXPECT_GT(FindCrossings(mesh).overlaps.pairs, 0u);
}

// A block over the plate's edge: the part over the plate is shared, the rest of its bottom and
// the rest of the plate's top stay each body's own.
TEST(Imprint, OverhangKeepsEachBodysOwnPart) {
  RawMesh mesh = BlockOnPlate(8.0f, 3.1f);
  ASSERT_TRUE(RepairMesh(mesh, RepairOptions{}).ok());
  const ImprintResult imprint = ImprintContacts(mesh);
  ASSERT_EQ(imprint.contacts.size(), 1u);
  EXPECT_NEAR(imprint.contacts[0].area, 8.0, 1e-4);
  EXPECT_EQ(FindCrossings(mesh).overlaps.pairs, 0u);
  const Parts parts = SimplifyAndMeasure(BlockOnPlate(8.0f, 3.1f));
  ASSERT_EQ(parts.input.size(), 2u);
  EXPECT_NEAR(parts.input[0], 32.0, 1e-4);
  EXPECT_NEAR(parts.input[1], 100.0, 1e-4);
}

// Corners of the block that coincide with the plate's grid points in the plane but lie a little
// above them (farther than the weld tolerance, within the plane's): they become the plate's.
TEST(Imprint, CornersOnTheOthersCornersBecomeThem) {
  RawMesh mesh = BlockOnPlate(2.0f, 2.0f, 4e-6f);
  absl::StatusOr<RepairResult> plain = RepairMesh(mesh, RepairOptions{});
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain->report.count(RepairKind::kWeldedVertex), 0u) << plain->report.Details();
  ASSERT_GT(FindCrossings(mesh).overlaps.pairs, 0u);
  const ImprintResult imprint = ImprintContacts(mesh);
  ASSERT_EQ(imprint.contacts.size(), 1u) << (imprint.left.empty() ? "" : imprint.left[0].reason);
  EXPECT_GT(imprint.contacts[0].corners_merged, 0u);
  EXPECT_NEAR(imprint.contacts[0].area, 16.0, 1e-3);
  EXPECT_EQ(FindCrossings(mesh).overlaps.pairs, 0u);
  const Parts parts = SimplifyAndMeasure(BlockOnPlate(2.0f, 2.0f, 4e-6f));
  ASSERT_EQ(parts.input.size(), 2u);
  EXPECT_NEAR(parts.input[0], 32.0, 1e-3);
  EXPECT_NEAR(parts.input[1], 100.0, 1e-3);
}

// The same on a tilted assembly (no plane on an axis, corners rounded to float there).
TEST(Imprint, TiltedContact) {
  RawMesh mesh = testing::TurnedSkew(BlockOnPlate(3.2f, 2.9f));
  ASSERT_TRUE(RepairMesh(mesh, RepairOptions{}).ok());
  ASSERT_GT(FindCrossings(mesh).overlaps.pairs, 0u);
  const ImprintResult imprint = ImprintContacts(mesh);
  ASSERT_EQ(imprint.contacts.size(), 1u) << (imprint.left.empty() ? "" : imprint.left[0].reason);
  EXPECT_NEAR(imprint.contacts[0].area, 16.0, 1e-3);
  EXPECT_EQ(FindCrossings(mesh).overlaps.pairs, 0u);
  EXPECT_EQ(FindCrossings(mesh).pairs, 0u);
  const Parts parts = SimplifyAndMeasure(testing::TurnedSkew(BlockOnPlate(3.2f, 2.9f)));
  ASSERT_EQ(parts.input.size(), 2u);
  EXPECT_NEAR(parts.input[0], 32.0, 1e-3);
  EXPECT_NEAR(parts.input[1], 100.0, 1e-3);
}

// Each piece keeps the group and field value of the facet it lies in; a shared piece those of
// the facet facing +z (the plate's top).
TEST(Imprint, GroupsAndFieldsFollowTheFacets) {
  RawMesh mesh = BlockOnPlate(3.2f, 2.9f);
  const size_t plate_faces = MakeBox({10, 10, 1}, {5, 5, 1}).num_faces();
  mesh.face_groups.resize(mesh.num_faces());
  FaceField field{"facet", {}};
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_groups[f] = f < plate_faces ? 1 : 2;
    field.values.push_back(float(f));
  }
  mesh.face_fields.push_back(field);
  const RawMesh input = mesh;
  absl::StatusOr<RepairResult> r = RepairMesh(mesh, Imprinting());
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->facet_origin.size(), mesh.num_faces());
  size_t shared_on_plate = 0;
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    const uint32_t from = r->facet_origin[f];
    EXPECT_EQ(mesh.face_groups[f], input.face_groups[from]);
    EXPECT_EQ(mesh.face_fields[0].values[f], float(from));
    const float* p[3];
    for (int c = 0; c < 3; ++c) p[c] = &mesh.positions[3 * size_t{mesh.triangles[3 * f + c]}];
    const bool at_contact = p[0][2] == 1.0f && p[1][2] == 1.0f && p[2][2] == 1.0f;
    const double nz =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    if (at_contact && mesh.face_groups[f] == 1) {
      EXPECT_GT(nz, 0.0);
      ++shared_on_plate;
    }
    if (at_contact) {
      EXPECT_EQ(mesh.face_groups[f], 1u);  // the block's bottom is all shared
    }
  }
  EXPECT_GT(shared_on_plate, 0u);
  for (uint32_t v : r->vertex_origin) {
    if (v != kNoInputVertex) {
      EXPECT_LT(v, input.num_vertices());
    }
  }
}

// Boxes that cross each other share faces in their planes facing the same way: no contact of
// bodies touching from outside. Left as exported, said why, and the mesh still simplifies.
TEST(Imprint, SameFacingOverlapIsLeftAsItWas) {
  RawMesh mesh = MakeBox({2, 2, 2}, {2, 2, 2});
  Append(mesh, MakeBox({2, 2, 2}, {3, 3, 3}), {1, 0, 0});
  RawMesh plain = mesh;
  ASSERT_TRUE(RepairMesh(plain, RepairOptions{}).ok());
  absl::StatusOr<RepairResult> r = RepairMesh(mesh, Imprinting());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->report.count(RepairKind::kImprintedContact), 0u);
  EXPECT_GT(r->report.count(RepairKind::kContactLeft), 0u);
  EXPECT_NE(r->report.Details().find("facing the same way"), std::string::npos)
      << r->report.Details();
  EXPECT_EQ(mesh.positions, plain.positions);
  EXPECT_EQ(mesh.triangles, plain.triangles);
  RawMesh again = MakeBox({2, 2, 2}, {2, 2, 2});
  Append(again, MakeBox({2, 2, 2}, {3, 3, 3}), {1, 0, 0});
  EXPECT_TRUE(PrepareMesh(again, Imprinting()).ok());
}

}  // namespace
}  // namespace femsimp
