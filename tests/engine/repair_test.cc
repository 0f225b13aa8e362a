#include "engine/repair.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "engine/mesh_checks.h"
#include "engine/prepare.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

// Substring checks without gmock (the engine tests link gtest only).
#define EXPECT_HAS(text, part)                               \
  EXPECT_NE(std::string(text).find(part), std::string::npos) \
      << "missing: " << (part) << "\nin: " << (text)
#define EXPECT_HAS_NOT(text, part)                           \
  EXPECT_EQ(std::string(text).find(part), std::string::npos) \
      << "found: " << (part) << "\nin: " << (text)

// Appends an axis-aligned cube of 8 vertices and 12 outward facets; its first vertex is the
// corner (x, y, z), vertex i the corner at offsets (i & 1, i >> 1 & 1, i >> 2 & 1) * size.
void AddCube(RawMesh& m, float x, float y, float z, float size = 1) {
  const uint32_t base = static_cast<uint32_t>(m.num_vertices());
  for (uint32_t i = 0; i < 8; ++i)
    m.positions.insert(m.positions.end(),
                       {x + size * (i & 1), y + size * (i >> 1 & 1), z + size * (i >> 2 & 1)});
  // Quads counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
  const uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads)
    m.triangles.insert(m.triangles.end(), {base + q[0], base + q[1], base + q[2], base + q[0],
                                           base + q[2], base + q[3]});
}

RawMesh Cube() {
  RawMesh m;
  AddCube(m, 0, 0, 0);
  return m;
}

// Groups and one field, both telling the facet's input number, to see them follow the facets.
void NumberFacets(RawMesh& m) {
  m.face_groups.clear();
  m.face_fields = {{"pressure", {}}};
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    m.face_groups.push_back(100 + f);
    m.face_fields[0].values.push_back(0.5f * f);
  }
}

void Flip(RawMesh& m, size_t f) { std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]); }

void AppendFacet(RawMesh& m, std::initializer_list<uint32_t> t) {
  m.triangles.insert(m.triangles.end(), t);
}

RepairResult Repair(RawMesh& m, RepairOptions options = {}) {
  absl::StatusOr<RepairResult> r = RepairMesh(m, options);
  EXPECT_TRUE(r.ok()) << r.status();
  return r.ok() ? *std::move(r) : RepairResult{};
}

void ExpectBuilds(const RawMesh& m) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
}

// The records of one kind, joined, for substring checks.
std::string Records(const RepairReport& report, RepairKind kind) {
  std::string s;
  for (const RepairRecord& r : report.records)
    if (r.kind == kind) s += r.ToString() + "\n";
  return s;
}

// Each facet's corners as coordinates: the facets, whatever the vertex numbering.
std::vector<float> CornerPoints(const RawMesh& m) {
  std::vector<float> points;
  for (uint32_t v : m.triangles)
    points.insert(points.end(), &m.positions[3 * v], &m.positions[3 * v] + 3);
  return points;
}

void ExpectSameMesh(const RawMesh& a, const RawMesh& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.face_groups, b.face_groups);
  ASSERT_EQ(a.face_fields.size(), b.face_fields.size());
  for (size_t i = 0; i < a.face_fields.size(); ++i) {
    EXPECT_EQ(a.face_fields[i].name, b.face_fields[i].name);
    EXPECT_EQ(a.face_fields[i].values, b.face_fields[i].values);
  }
}

TEST(Repair, CleanMeshesComeBackUntouched) {
  RawMesh touching;  // two cubes meeting at (1, 1, 1), each with its own vertex there
  AddCube(touching, 0, 0, 0);
  AddCube(touching, 1, 1, 1);
  for (RawMesh clean : {Cube(), testing::Octahedron(), testing::FlatGrid(4), touching,
                        testing::LoadTestMesh("fandisk.off")}) {
    NumberFacets(clean);
    RawMesh m = clean;
    RepairResult r = Repair(m);
    ExpectSameMesh(m, clean);
    EXPECT_EQ(r.report.num_changes(), 0u) << r.report.Details();
    EXPECT_TRUE(r.report.records.empty());
    EXPECT_EQ(r.report.Summary(), "repair: no changes");
    EXPECT_EQ(r.facet_origin.size(), clean.num_faces());
    EXPECT_EQ(r.vertex_origin.size(), clean.num_vertices());
  }
}

TEST(Repair, FlippedFacet) {
  RawMesh m = Cube();
  NumberFacets(m);
  const RawMesh clean = m;
  Flip(m, 5);
  EXPECT_FALSE(Mesh::Build(m).ok());
  RepairResult r = Repair(m);
  ExpectSameMesh(m, clean);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), 1u);
  EXPECT_EQ(r.report.num_changes(), 1u) << r.report.Details();
  ASSERT_EQ(r.report.records.size(), 1u);
  EXPECT_EQ(r.report.records[0].facet, 5);
  // Facet 5 is the second half of the -y quad, (0, 5, 4): centroid (1/3, 0, 2/3).
  EXPECT_NEAR(r.report.records[0].at[0], 1.0 / 3, 1e-7);
  EXPECT_EQ(r.report.records[0].at[1], 0.0);
  EXPECT_HAS(r.report.Details(), "flipped facet 5 at (0.333333333, 0, 0.666666667)");
  EXPECT_EQ(r.report.Summary(), "repair: flipped 1 facet");
}

TEST(Repair, InsideOutComponentIsTurnedOutward) {
  RawMesh m;
  AddCube(m, 0, 0, 0);
  AddCube(m, 3, 0, 0);
  const RawMesh clean = m;
  for (size_t f = 12; f < 24; ++f) Flip(m, f);
  ExpectBuilds(m);  // consistent, only inside out
  RepairResult r = Repair(m);
  ExpectSameMesh(m, clean);
  EXPECT_GT(testing::SignedVolume(m), 1.99);
  EXPECT_EQ(r.report.count(RepairKind::kReversedComponent), 1u);
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), 12u);
  EXPECT_HAS(Records(r.report, RepairKind::kReversedComponent), "inside-out component (facet 12)");
  EXPECT_HAS(Records(r.report, RepairKind::kFlippedFacet), "flipped facet 23 at");
  EXPECT_HAS_NOT(Records(r.report, RepairKind::kFlippedFacet), "flipped facet 11 ");

  RepairOptions keep;
  keep.orient_outward = false;
  RawMesh inside_out = m;
  for (size_t f = 0; f < 12; ++f) Flip(inside_out, f);
  const RawMesh before = inside_out;
  EXPECT_EQ(Repair(inside_out, keep).report.num_changes(), 0u);
  ExpectSameMesh(inside_out, before);
}

// A part with a cavity is an outer shell facing out and the cavity's wall facing in (into the
// cavity): repair keeps that, and turns a cavity wall that faces out (as gmsh writes the sphere of
// a box minus a sphere) so that the mesh bounds the solid: its volume is the box's less the
// cavity's. An island in the cavity faces out again; a box beside the part is not in it.
TEST(Repair, CavityWallsFaceIntoTheCavity) {
  RawMesh m;
  AddCube(m, 0, 0, 0, 10);    // the part, facets 0-11
  AddCube(m, 2, 2, 2, 6);     // its cavity, 12-23
  AddCube(m, 4, 4, 4, 2);     // an island in the cavity, 24-35
  AddCube(m, 12, 0, 0, 1);    // a box beside the part, 36-47
  AddCube(m, 9.5, 9.5, 9.5);  // a box crossing the part's corner (out at some facets), 48-59
  for (size_t f = 12; f < 24; ++f) Flip(m, f);  // the cavity's wall facing in: right
  const RawMesh solid = m;
  const double volume = 1000 - 216 + 8 + 1 + 1;
  EXPECT_NEAR(testing::SignedVolume(solid), volume, 1e-9);
  {
    RawMesh same = solid;
    RepairResult r = Repair(same);
    EXPECT_EQ(r.report.num_changes(), 0u) << r.report.Details();
    ExpectSameMesh(same, solid);
  }
  // Every shell facing out: the cavity's wall is turned in, and only it.
  RawMesh outward = solid;
  for (size_t f = 12; f < 24; ++f) Flip(outward, f);
  RepairResult r = Repair(outward);
  ExpectSameMesh(outward, solid);
  EXPECT_EQ(r.report.count(RepairKind::kReversedComponent), 1u);
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), 12u);
  EXPECT_HAS(Records(r.report, RepairKind::kReversedComponent),
             "closed component of 12 facets lies inside another (the wall of a cavity) but faced "
             "outward; 12 facets flipped to face into the cavity");
  // Every shell inside out: each is turned the right way.
  RawMesh inverted = solid;
  for (size_t f = 0; f < inverted.num_faces(); ++f) Flip(inverted, f);
  r = Repair(inverted);
  ExpectSameMesh(inverted, solid);
  EXPECT_EQ(r.report.count(RepairKind::kReversedComponent), 5u);
  EXPECT_NEAR(testing::SignedVolume(inverted), volume, 1e-9);
}

// A body inside another, each written closed on its own: the inner one's surface comes twice,
// facing both ways (the outer body's copy faces into it). One copy is kept as the wall of a
// cavity, and that the body inside is lost to the volume is reported, whichever body the file
// lists first. A cavity written once, and a body written twice facing both ways inside nothing,
// are not.
TEST(Repair, ASurfaceTwoBodiesShareWholeIsReported) {
  const auto coated = [](bool insert_first) {
    RawMesh m;
    RawMesh insert, coating;
    AddCube(insert, 2, 2, 2, 6);
    AddCube(coating, 0, 0, 0, 10);
    AddCube(coating, 2, 2, 2, 6);
    for (size_t f = 12; f < 24; ++f) Flip(coating, f);
    testing::Append(m, insert_first ? insert : coating, {0, 0, 0});
    testing::Append(m, insert_first ? coating : insert, {0, 0, 0});
    return m;
  };
  for (const bool insert_first : {true, false}) {
    SCOPED_TRACE(insert_first ? "the insert first" : "the coating first");
    RawMesh m = coated(insert_first);
    RepairResult r = Repair(m);
    EXPECT_EQ(r.report.count(RepairKind::kDuplicateFacet), 12u);
    EXPECT_EQ(r.report.count(RepairKind::kSharedShellLeft), 1u) << r.report.Details();
    EXPECT_HAS(Records(r.report, RepairKind::kSharedShellLeft),
               "closed surface of 12 facets inside another body, every facet of it written "
               "twice, facing both ways");
    EXPECT_HAS(Records(r.report, RepairKind::kSharedShellLeft), "(volume 216)");
    EXPECT_NEAR(testing::SignedVolume(m), 1000 - 216, 1e-9);  // what is kept: a cavity
  }
  RawMesh cavity;  // the coating alone
  AddCube(cavity, 0, 0, 0, 10);
  AddCube(cavity, 2, 2, 2, 6);
  for (size_t f = 12; f < 24; ++f) Flip(cavity, f);
  EXPECT_EQ(Repair(cavity).report.count(RepairKind::kSharedShellLeft), 0u);
  RawMesh twice;  // a body written twice, facing both ways
  AddCube(twice, 0, 0, 0, 10);
  AddCube(twice, 0, 0, 0, 10);
  for (size_t f = 12; f < 24; ++f) Flip(twice, f);
  RepairResult r = Repair(twice);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateFacet), 12u);
  EXPECT_EQ(r.report.count(RepairKind::kSharedShellLeft), 0u);
}

TEST(Repair, DuplicateFacetsEitherOrientation) {
  RawMesh m = Cube();
  NumberFacets(m);
  const RawMesh clean = m;
  // Facet 12 repeats facet 3, facet 13 is facet 7 turned over (a zero-volume double wall).
  AppendFacet(m, {m.triangles[9], m.triangles[10], m.triangles[11]});
  AppendFacet(m, {m.triangles[21], m.triangles[23], m.triangles[22]});
  m.face_groups.insert(m.face_groups.end(), {7, 8});
  m.face_fields[0].values.insert(m.face_fields[0].values.end(), {-1.f, -2.f});
  EXPECT_FALSE(Mesh::Build(m).ok());
  RepairResult r = Repair(m);
  ExpectSameMesh(m, clean);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateFacet), 2u);
  EXPECT_EQ(r.report.num_changes(), 2u) << r.report.Details();
  const std::string records = Records(r.report, RepairKind::kDuplicateFacet);
  EXPECT_HAS(records, "duplicate facet 12 at");
  EXPECT_HAS(records, "same vertices as facet 3\n");
  EXPECT_HAS(records, "duplicate facet 13 at");
  EXPECT_HAS(records, "same vertices as facet 7, opposite orientation");
  EXPECT_EQ(r.facet_origin.size(), 12u);
  EXPECT_EQ(r.facet_origin.back(), 11u);
}

TEST(Repair, DegenerateFacetsGroupsAndFieldsFollow) {
  RawMesh m = Cube();
  NumberFacets(m);
  const RawMesh clean = m;
  // A facet repeating an index and a zero-area one through a new vertex on edge (0, 1), both
  // inserted before facet 4, with their own group and field values.
  m.positions.insert(m.positions.end(), {0.5f, 0, 0});
  m.triangles.insert(m.triangles.begin() + 12, {0, 0, 1, 0, 8, 1});
  m.face_groups.insert(m.face_groups.begin() + 4, {7, 8});
  m.face_fields[0].values.insert(m.face_fields[0].values.begin() + 4, {-1.f, -2.f});
  EXPECT_FALSE(Mesh::Build(m).ok());
  RepairResult r = Repair(m);
  ExpectSameMesh(m, clean);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kDegenerateFacet), 2u);
  EXPECT_EQ(r.report.count(RepairKind::kUnreferencedVertex), 1u);  // vertex 8, used by facet 5
  const std::string records = Records(r.report, RepairKind::kDegenerateFacet);
  EXPECT_HAS(records, "degenerate facet 4 at (0.333333333, 0, 0): repeats a vertex");
  EXPECT_HAS(records, "degenerate facet 5 at (0.5, 0, 0): zero area");
  EXPECT_HAS(Records(r.report, RepairKind::kUnreferencedVertex),
             "unreferenced vertex 8 at (0.5, 0, 0): its facets were removed");
  EXPECT_EQ(r.facet_origin[4], 6u);
}

// Cube facet 4 (0, 1, 5) split at T vertices on its edge (0, 1) into a fan: (0, t0, 5),
// (t0, t1, 5), ..., (tn, 1, 5), the vertices t appended at the given x on y = z = 0. Facet 9
// (0, 3, 1) keeps the whole edge: the zero-area slivers appended by the caller close the gap.
RawMesh TJunctionCube(std::initializer_list<float> xs) {
  RawMesh m = Cube();
  NumberFacets(m);
  std::vector<uint32_t> fan = {0};
  for (float x : xs) {
    fan.push_back(static_cast<uint32_t>(m.num_vertices()));
    m.positions.insert(m.positions.end(), {x, 0, 0});
  }
  fan.push_back(1);
  m.triangles[3 * 4 + 1] = fan[1];
  for (size_t i = 1; i + 1 < fan.size(); ++i) {
    AppendFacet(m, {fan[i], fan[i + 1], 5});
    m.face_groups.push_back(104);
    m.face_fields[0].values.push_back(2.f);
  }
  return m;
}

// A facet with a group and field value of its own (a sliver's: none survives repair).
void AppendNumberedFacet(RawMesh& m, std::initializer_list<uint32_t> t, int group = -1) {
  AppendFacet(m, t);
  m.face_groups.push_back(group);
  m.face_fields[0].values.push_back(-1.f);
}

void ExpectClosedCube(const RawMesh& m) {
  ExpectBuilds(m);
  const SoupTopology topology = TopologyOf(m);
  EXPECT_EQ(topology.boundary_edges, 0);
  EXPECT_EQ(topology.components, 1);
  EXPECT_EQ(topology.euler(), TopologyOf(Cube()).euler());
  EXPECT_NEAR(testing::SignedVolume(m), 1.0, 1e-6);
}

// Strict mode accepts `m` (nothing Mesh::Build refuses) and changes nothing.
void ExpectStrictModeLeavesAlone(RawMesh m) {
  const RawMesh before = m;
  RepairOptions strict;
  strict.mode = RepairMode::kOff;
  EXPECT_TRUE(RepairMesh(m, strict).ok());
  ExpectSameMesh(m, before);
}

TEST(Repair, TJunctionSliverSplitsTheFacetAcross) {
  RawMesh m = TJunctionCube({0.5f});  // facets 0-11, 12 = (8, 1, 5)
  AppendNumberedFacet(m, {0, 1, 8});  // facet 13
  const SoupTopology input = TopologyOf(m);
  EXPECT_EQ(input.boundary_edges, 0);  // closed and manifold with the sliver
  RepairResult r = Repair(m);
  ExpectClosedCube(m);
  EXPECT_EQ(TopologyOf(m).euler(), input.euler());
  EXPECT_EQ(r.report.count(RepairKind::kDegenerateFacet), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 1u);
  EXPECT_EQ(r.report.num_changes(), 2u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kDegenerateFacet),
             "degenerate facet 13 at (0.5, 0, 0): zero area (its corners lie on a line); closed "
             "a T-junction at vertex 8: split facet 9 there");
  EXPECT_HAS(Records(r.report, RepairKind::kSplitEdge),
             "split edge of facet 9 at (0.5, 0, 0): edge from vertex 1 to vertex 0 split at "
             "vertex 8 (a T-junction closed by degenerate facet 13): facets (8, 3, 1) and "
             "(8, 0, 3)");
  ASSERT_EQ(r.report.records.size(), 2u);
  EXPECT_EQ(r.report.records[1].kind, RepairKind::kSplitEdge);
  EXPECT_EQ(r.report.records[1].facet, 9);
  EXPECT_EQ(r.report.records[1].vertex, 8);
  EXPECT_HAS(r.report.Summary(), "removed 1 degenerate facet, split 1 edge at a T-junction");
  // Facet 9's halves in its place, with its group and field value; no point moved.
  EXPECT_EQ(r.facet_origin, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 10, 11, 12}));
  EXPECT_EQ(std::vector<uint32_t>(m.triangles.begin() + 27, m.triangles.begin() + 33),
            (std::vector<uint32_t>{8, 3, 1, 8, 0, 3}));
  EXPECT_EQ(m.face_groups[9], 109);
  EXPECT_EQ(m.face_groups[10], 109);
  EXPECT_EQ(m.face_fields[0].values[10], 4.5f);
  EXPECT_EQ(r.vertex_origin, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));

  // Strict mode names the sliver and changes nothing.
  RawMesh strict_mesh = TJunctionCube({0.5f});
  AppendNumberedFacet(strict_mesh, {0, 1, 8});
  const RawMesh before = strict_mesh;
  RepairOptions strict;
  strict.mode = RepairMode::kOff;
  absl::StatusOr<RepairResult> refused = RepairMesh(strict_mesh, strict);
  ASSERT_FALSE(refused.ok());
  ExpectSameMesh(strict_mesh, before);
  const std::string message(refused.status().message());
  EXPECT_HAS(message, "repair is off and the mesh has 1 defect (1 degenerate facet)");
  EXPECT_HAS(message, "degenerate facet 13 at (0.5, 0, 0): zero area");
  EXPECT_HAS_NOT(message, "split");
}

// A CAD exporter writing the T vertex in single precision puts it off the edge by the rounding:
// the facet closing the T-junction is a needle, not of zero area, which Mesh::Build accepts and
// tetgen aborts on. Within the weld tolerance of the edge it is a sliver like a zero-area one;
// beyond it, a thin facet the repair leaves alone.
TEST(Repair, TJunctionNeedleWithinTheWeldToleranceIsASliver) {
  const auto needle_cube = [](float off) {
    RawMesh m = TJunctionCube({0.5f});  // T vertex 8 on edge (0, 1) of the face y = 0
    m.positions[3 * 8 + 2] = off;       // moved off the edge within that face
    AppendNumberedFacet(m, {0, 1, 8});  // facet 13
    return m;
  };
  RawMesh m = needle_cube(1e-8f);  // the weld tolerance: 1e-7 of the diagonal, 1.7e-7
  ASSERT_TRUE(Mesh::Build(m).ok());
  RepairResult r = Repair(m);
  ExpectClosedCube(m);
  EXPECT_EQ(r.report.count(RepairKind::kDegenerateFacet), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 1u);
  EXPECT_HAS(Records(r.report, RepairKind::kDegenerateFacet),
             "degenerate facet 13 at (0.5, 0, 3.33333331e-09): a needle (its corners lie on a "
             "line within the weld tolerance: 1e-08 from it); closed a T-junction at vertex 8: "
             "split facet 9 there");
  EXPECT_EQ(m.num_faces(), 14u);  // the needle out, facet 9 in two

  // Thin beyond the weld tolerance: a facet like any other.
  RawMesh thin = needle_cube(1e-5f);
  const RawMesh before = thin;
  r = Repair(thin);
  EXPECT_EQ(r.report.num_changes(), 0u) << r.report.Details();
  ExpectSameMesh(thin, before);
  // Strict mode keeps the zero-area test of Mesh::Build: the needle is not a defect there.
  ExpectStrictModeLeavesAlone(needle_cube(1e-8f));
}

TEST(Repair, ChainsOfTJunctionSliversAlongOneEdge) {
  // Two T vertices on edge (0, 1): 8 at x = 0.25, 9 at 0.5. Two slivers close the gap, either
  // nested on the long edge (A: (0, 1, 8) then (8, 1, 9)) or along it ((0, 9, 8) then (0, 1, 9)),
  // in either order: the second waits until the first has split facet 9.
  struct Chain {
    std::initializer_list<uint32_t> first, second;
  };
  for (const Chain& chain : {Chain{{0, 1, 8}, {8, 1, 9}}, Chain{{0, 9, 8}, {0, 1, 9}}})
    for (bool reversed : {false, true}) {
      SCOPED_TRACE(reversed);
      RawMesh m = TJunctionCube({0.25f, 0.5f});  // facets 0-11, 12 and 13 the fan
      AppendNumberedFacet(m, reversed ? chain.second : chain.first);
      AppendNumberedFacet(m, reversed ? chain.first : chain.second);
      const int64_t euler = TopologyOf(m).euler();
      RepairResult r = Repair(m);
      ExpectClosedCube(m);
      EXPECT_EQ(TopologyOf(m).euler(), euler);
      EXPECT_EQ(r.report.count(RepairKind::kDegenerateFacet), 2u) << r.report.Details();
      EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 2u) << r.report.Details();
      EXPECT_EQ(r.report.num_changes(), 4u) << r.report.Details();
      const std::string splits = Records(r.report, RepairKind::kSplitEdge);
      EXPECT_HAS(splits, "split edge of facet 9 at (0.25, 0, 0)");
      EXPECT_HAS(splits, "split edge of facet 9 at (0.5, 0, 0)");
      EXPECT_HAS_NOT(Records(r.report, RepairKind::kDegenerateFacet), "left open");
      // Facet 9 became three facets, in its place.
      EXPECT_EQ(r.facet_origin,
                (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 10, 11, 12, 13}));
      for (size_t f = 9; f < 12; ++f) EXPECT_EQ(m.face_groups[f], 109);
    }
}

TEST(Repair, UnsafeTJunctionSplitsFallBackToRemovingTheSliver) {
  // Both sides of edge (0, 1) have a T vertex (8 in facet 4's fan, 9 in facet 9's), and each
  // side's sliver has the other as its only neighbour across the edge: no sliver split is safe,
  // both slivers are removed, and the crack between 0-8-1 and 0-9-1 they leave is zipped (each
  // side split at the other's vertex).
  RawMesh m = TJunctionCube({0.5f});                     // facets 0-11, 12 = (8, 1, 5)
  m.positions.insert(m.positions.end(), {0.75f, 0, 0});  // vertex 9
  m.triangles[3 * 9 + 2] = 9;                            // facet 9: (0, 3, 9)
  AppendNumberedFacet(m, {9, 3, 1}, 109);                // facet 13: the rest of facet 9
  AppendNumberedFacet(m, {0, 1, 8});                     // facet 14
  AppendNumberedFacet(m, {1, 0, 9});                     // facet 15
  RepairResult r = Repair(m);
  ExpectClosedCube(m);
  EXPECT_EQ(r.report.count(RepairKind::kDegenerateFacet), 2u);
  const std::string records = Records(r.report, RepairKind::kDegenerateFacet);
  EXPECT_HAS(records,
             "degenerate facet 14 at (0.5, 0, 0): zero area (its corners lie on a line); not "
             "split at its T vertex 8: the other facets on its longest edge have zero area too");
  EXPECT_HAS(records, "degenerate facet 15 at");
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 2u) << r.report.Details();
  const std::string splits = Records(r.report, RepairKind::kSplitEdge);
  EXPECT_HAS(splits,
             "split edge of facet 9 at (0.5, 0, 0): edge from vertex 9 to vertex 0 split "
             "at vertex 8 (a T-junction: the facets across the crack have a vertex there)");
  EXPECT_HAS(splits,
             "split edge of facet 12 at (0.75, 0, 0): edge from vertex 8 to vertex 1 "
             "split at vertex 9");

  // A split that would add an edge that exists already (here 8-3, of an extra facet) is not
  // made either, by the sliver or by the zip.
  m = TJunctionCube({0.5f});
  AppendNumberedFacet(m, {3, 8, 6});  // facet 13: not a sliver, its edge 3-8 is in the way
  AppendNumberedFacet(m, {0, 1, 8});  // facet 14
  r = Repair(m);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 0u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kDegenerateFacet),
             "degenerate facet 14 at (0.5, 0, 0): zero area (its corners lie on a line); not "
             "split at its T vertex 8: splitting facet 9 there would add an edge to vertex 3 "
             "that exists already");
}

TEST(Repair, TJunctionCracksAreZipped) {
  // Facet 4's side of edge (0, 1) has T vertices, facet 9's has the whole edge and nothing
  // closes the crack between them (faces tessellated one by one): facet 9 is split at each.
  for (const std::vector<float>& xs : {std::vector<float>{0.5f}, {0.25f, 0.5f, 0.75f}}) {
    SCOPED_TRACE(xs.size());
    RawMesh m = xs.size() == 1 ? TJunctionCube({0.5f}) : TJunctionCube({0.25f, 0.5f, 0.75f});
    EXPECT_EQ(TopologyOf(m).boundary_edges, int(xs.size()) + 2);
    RepairResult r = Repair(m);
    ExpectClosedCube(m);
    EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), xs.size()) << r.report.Details();
    EXPECT_EQ(r.report.num_changes(), xs.size()) << r.report.Details();
    EXPECT_HAS(Records(r.report, RepairKind::kSplitEdge),
               "split edge of facet 9 at (0.5, 0, 0): edge from vertex 1 to vertex 0 split at "
               "vertex ");
    // Facet 9's pieces in its place, with its group and field value; no point moved.
    std::vector<uint32_t> origin = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    origin.insert(origin.end(), xs.size(), 9);
    for (uint32_t f = 10; f < 12 + xs.size(); ++f) origin.push_back(f);
    EXPECT_EQ(r.facet_origin, origin);
    for (size_t f = 9; f < 10 + xs.size(); ++f) {
      EXPECT_EQ(m.face_groups[f], 109);
      EXPECT_EQ(m.face_fields[0].values[f], 4.5f);
    }
    // Strict mode: an open crack is not a defect; nothing changes.
    ExpectStrictModeLeavesAlone(xs.size() == 1 ? TJunctionCube({0.5f})
                                               : TJunctionCube({0.25f, 0.5f, 0.75f}));
  }
}

TEST(Repair, CrackBesideAMissingFacetIsZippedWhereItCloses) {
  // As TJunctionCracksAreZipped, but the fan's last facet (10, 1, 5) is missing: the crack
  // closes along 0-8-9-10 only. Facet 9 is split there all the same, and the hole left is the
  // missing facet's triangle, not a loop running along the crack to vertex 1 and back (whose
  // fill would lie on facet 9's pieces, folded).
  RawMesh m = TJunctionCube({0.25f, 0.5f, 0.75f});  // facets 12-14 the fan
  m.triangles.resize(3 * 14);
  m.face_groups.resize(14);
  m.face_fields[0].values.resize(14);
  RepairResult r = Repair(m);
  ExpectClosedCube(m);
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 3u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFoldLeft), 0u) << r.report.Details();
  EXPECT_EQ(r.report.num_changes(), 4u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole), "a hole of 3 edges (vertices ");
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole), " closed by 1 facet of area 0.125 ");
}

TEST(Repair, TJunctionZipTakesFloatRoundingAndNarrowGaps) {
  // Edge (0, 1) slanted, so that its third is not a float: the T vertex, rounded, lies off the
  // segment by the float coordinates' rounding, which the zip takes even without a weld
  // tolerance. A T vertex a thousandth off the segment (as one on a curve is off the chord) is
  // zipped too, and its record says how far; one a fifth of the edge off is a gap beyond the
  // zip's eighth, a hole of three edges, which a facet fills.
  for (float off : {0.f, 1e-3f, 0.2f}) {
    SCOPED_TRACE(off);
    RawMesh m = TJunctionCube({1.f / 3});
    m.positions[3 * 1 + 1] = 0.3f;  // vertex 1 at (1, 0.3, 0): the -y faces are no longer flat
    m.positions[3 * 8 + 1] = 0.3f / 3 + off;
    RepairOptions options;
    options.weld_tolerance = 0;
    RepairResult r = Repair(m, options);
    ExpectBuilds(m);
    EXPECT_EQ(TopologyOf(m).boundary_edges, 0);
    EXPECT_EQ(r.report.num_changes(), 1u) << r.report.Details();
    const std::string splits = Records(r.report, RepairKind::kSplitEdge);
    if (off == 0) {
      EXPECT_HAS(splits,
                 "split at vertex 8 (a T-junction: the facets across the crack have a "
                 "vertex there)");
    } else if (off < 0.1f) {
      EXPECT_HAS(splits,
                 "split at vertex 8 (a T-junction: the facets across the crack have a "
                 "vertex there, 0.000958 off the edge)");
    } else {
      EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
      EXPECT_HAS(Records(r.report, RepairKind::kFilledHole),
                 "a hole of 3 edges (vertices 0, 8, 1)");
    }
  }
}

// Each face of a box tessellated on its own: the four sides from a box cut in thirds, the top
// and the bottom from one cut in halves. Along the eight edges where they meet the two sides'
// vertices interleave (thirds and halves) and share only the box's corners, so no walk along
// one side's open edges reaches the other's (a CAD exporter that meshes every face alone). Each
// edge is split at the other side's vertices inside it (three per box edge), and the box
// closes with no point moved. With the top lifted by 0.4 % of the diagonal (a gap, not a
// crack) only the bottom closes.
RawMesh InterleavedBox(float lift) {
  const RawMesh thirds = testing::MakeBox({3, 3, 3}, {3, 3, 3});
  RawMesh halves = testing::MakeBox({3, 3, 3}, {2, 2, 2});
  const auto top_or_bottom = [](const RawMesh& box, size_t f) {
    const auto z = [&](int k) { return box.positions[3 * box.triangles[3 * f + k] + 2]; };
    return z(0) == z(1) && z(1) == z(2);
  };
  RawMesh m;
  m.positions = thirds.positions;
  for (size_t v = 0; v < halves.num_vertices(); ++v)
    if (halves.positions[3 * v + 2] == 3) halves.positions[3 * v + 2] += lift;
  m.positions.insert(m.positions.end(), halves.positions.begin(), halves.positions.end());
  const uint32_t base = static_cast<uint32_t>(thirds.num_vertices());
  for (size_t f = 0; f < thirds.num_faces(); ++f)
    if (!top_or_bottom(thirds, f))
      m.triangles.insert(m.triangles.end(), &thirds.triangles[3 * f], &thirds.triangles[3 * f + 3]);
  for (size_t f = 0; f < halves.num_faces(); ++f)
    if (top_or_bottom(halves, f))
      for (int k = 0; k < 3; ++k) m.triangles.push_back(base + halves.triangles[3 * f + k]);
  return m;
}

TEST(Repair, InterleavedCracksAreZipped) {
  RawMesh m = InterleavedBox(0);
  const std::vector<float> input_positions = m.positions;
  EXPECT_GT(TopologyOf(m).boundary_edges, 0);
  RepairResult r = Repair(m);
  ExpectBuilds(m);
  EXPECT_EQ(TopologyOf(m).boundary_edges, 0) << r.report.Details();
  EXPECT_NEAR(testing::SignedVolume(m), 27.0, 1e-9);
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 24u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 0u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), 0u) << r.report.Details();
  for (size_t v = 0; v < m.num_vertices(); ++v) {
    const uint32_t from = r.vertex_origin[v];
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(m.positions[3 * v + k], input_positions[3 * from + k]) << v;
  }

  m = InterleavedBox(0.02f);
  r = Repair(m);
  EXPECT_EQ(r.report.count(RepairKind::kSplitEdge), 12u) << r.report.Details();
  EXPECT_GT(TopologyOf(m).boundary_edges, 0);
}

// The bottom quad uses its own copies (8, 9) of vertices 0 and 1: the edges (0, 1), (0, 2) and
// (1, 3) are each open twice.
RawMesh CrackedCube(float offset) {
  RawMesh m = Cube();
  m.positions.insert(m.positions.end(), {offset, 0, 0, 1, 0, offset});
  for (size_t c = 24; c < 30; ++c) {  // facets 8 and 9: the -z quad (0, 2, 3, 1)
    if (m.triangles[c] == 0) m.triangles[c] = 8;
    if (m.triangles[c] == 1) m.triangles[c] = 9;
  }
  return m;
}

TEST(Repair, CrackIsStitched) {
  for (float offset : {0.f, 1e-8f}) {
    SCOPED_TRACE(offset);
    RawMesh m = CrackedCube(offset);
    EXPECT_EQ(TopologyOf(m).boundary_edges, 6);  // open, but Build accepts it
    RepairResult r = Repair(m);
    ExpectSameMesh(m, Cube());
    ExpectBuilds(m);
    EXPECT_EQ(TopologyOf(m).boundary_edges, 0);
    EXPECT_EQ(r.report.count(RepairKind::kWeldedVertex), 2u);
    EXPECT_EQ(r.report.count(RepairKind::kStitchedEdge), 3u);  // (0, 1), (0, 2), (1, 3)
    EXPECT_EQ(r.report.num_changes(), 5u) << r.report.Details();
    const std::string welded = Records(r.report, RepairKind::kWeldedVertex);
    EXPECT_HAS(welded, "welded vertex 8 (facet 8) at (");
    EXPECT_HAS(welded, "merged into vertex 0");
    EXPECT_HAS(welded, "welded vertex 9 (facet 9)");
    EXPECT_HAS(Records(r.report, RepairKind::kStitchedEdge),
               "stitched edge (facet 1) at (0, 0, 0): to (0, 1, 0): joins facets 1 and 8\n"
               "stitched edge (facet 2) at (1, 0, 0): to (1, 1, 0): joins facets 2 and 9\n"
               "stitched edge (facet 4) at (0, 0, 0): to (1, 0, 0): joins facets 4 and 9\n");
    EXPECT_NEAR(r.report.weld_tolerance_absolute, 1e-7 * std::sqrt(3.0), 1e-12);
    EXPECT_HAS(r.report.Summary(), "welded 2 vertices (tolerance 1e-07");
  }
  // Exact welding only: the exact crack closes, the near one stays open.
  RepairOptions exact;
  exact.weld_tolerance = 0;
  RawMesh m = CrackedCube(0);
  Repair(m, exact);
  ExpectSameMesh(m, Cube());
  m = CrackedCube(1e-8f);
  const RawMesh before = m;
  EXPECT_EQ(Repair(m, exact).report.num_changes(), 0u);
  ExpectSameMesh(m, before);
}

TEST(Repair, WeldKeepsLowestIndexAndDoesNotChain) {
  // A strip of two triangles whose shared edge is given three times, slightly apart.
  RawMesh m;
  m.positions = {0,     0, 0, 1, 0,     0, 0,     1,     0,   // 0 1 2
                 1,     1, 0,                                 // 3
                 1e-7f, 0, 0, 1, 1e-7f, 0, 2e-7f, 1e-7f, 0};  // 4 ~ 0, 5 ~ 1, 6 ~ 4 not 0
  m.triangles = {0, 1, 2, 5, 3, 2};
  m.triangles.insert(m.triangles.end(), {6, 4, 2});
  RepairOptions o;
  o.weld_tolerance = 1.2e-7 / std::sqrt(2.0);  // 1.2e-7 absolute: 4 -> 0 and 5 -> 1; 6 stays
  RepairResult r = Repair(m, o);
  EXPECT_EQ(r.report.count(RepairKind::kWeldedVertex), 2u) << r.report.Details();
  EXPECT_HAS(r.report.Details(),
             "welded vertex 5 (facet 1) at (1, 1.00000001e-07, "
             "0): merged into vertex 1");
  EXPECT_EQ(r.vertex_origin, (std::vector<uint32_t>{0, 1, 2, 3, 6}));
}

TEST(Repair, NonManifoldVertexIsSplit) {
  RawMesh m;
  AddCube(m, 0, 0, 0);
  AddCube(m, 1, 1, 1);
  // The second cube uses the first's vertex 7 for its corner 0 at (1, 1, 1).
  for (size_t c = 36; c < 72; ++c)
    if (m.triangles[c] == 8) m.triangles[c] = 7;
  EXPECT_FALSE(Mesh::Build(m).ok());
  RepairResult r = Repair(m);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kSplitVertex), 1u);
  EXPECT_EQ(r.report.num_changes(), 2u) << r.report.Details();  // and vertex 8 unused
  EXPECT_HAS(Records(r.report, RepairKind::kSplitVertex),
             "non-manifold vertex 7 (facet 2) at (1, 1, 1): 2 fans meet there "
             "(first facets 2, 12); 1 copies added");
  EXPECT_EQ(m.num_vertices(), 16u);
  EXPECT_EQ(r.vertex_origin.back(), 7u);
  EXPECT_EQ(TopologyOf(m).components, 2);
  EXPECT_NEAR(testing::SignedVolume(m), 2, 1e-6);
}

// Two unit cubes side by side whose common square x = 1 is one wall of two facets (in the first
// cube): its four sides are edges of three facets.
constexpr uint32_t kSkip = ~0u;

RawMesh CubesSharingAFace() {
  RawMesh m;
  AddCube(m, 0, 0, 0);
  AddCube(m, 1, 0, 0);
  // Second cube: drop its -x quad (facets 12, 13) and use the first cube's vertices there.
  m.triangles.erase(m.triangles.begin() + 36, m.triangles.begin() + 42);
  const uint32_t same[8] = {1, kSkip, 3, kSkip, 5, kSkip, 7, kSkip};
  for (size_t c = 36; c < m.triangles.size(); ++c)
    if (same[m.triangles[c] - 8] != kSkip) m.triangles[c] = same[m.triangles[c] - 8];
  return m;
}

TEST(Repair, NonManifoldEdgesAreKeptAsSeams) {
  RawMesh m = CubesSharingAFace();
  NumberFacets(m);
  const RawMesh before = m;
  RepairResult r = Repair(m);
  EXPECT_EQ(m.num_faces(), 22u);                     // nothing deleted
  EXPECT_EQ(CornerPoints(m), CornerPoints(before));  // same facets, renumbered vertices
  EXPECT_EQ(m.face_groups, before.face_groups);
  EXPECT_EQ(r.report.count(RepairKind::kSeamEdge), 4u);
  ASSERT_EQ(r.seams.size(), 4u);
  // Output vertices: 0..7, then 9, 11, 13, 15 (the unused 8, 10, 12, 14 dropped).
  EXPECT_EQ(r.seams[0].a, 1u);
  EXPECT_EQ(r.seams[0].b, 3u);
  EXPECT_EQ(r.seams[0].pa, (std::array<float, 3>{1, 0, 0}));
  EXPECT_EQ(r.seams[0].pb, (std::array<float, 3>{1, 1, 0}));
  EXPECT_EQ(r.seams[0].facets.size(), 3u);
  EXPECT_HAS(Records(r.report, RepairKind::kSeamEdge),
             "non-manifold edge (facet 3) at (1, 0, 0): to (1, 0, 1): shared by 3 "
             "facets (3, 4, 15)");
  EXPECT_HAS(r.report.Summary(), "kept 4 non-manifold edges as seams");
  EXPECT_EQ(r.report.count(RepairKind::kUnreferencedVertex), 4u);
  EXPECT_EQ(r.report.num_changes(), 4u) << r.report.Details();
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  ASSERT_FALSE(mesh.ok());
  EXPECT_HAS(std::string(mesh.status().message()), "non-manifold edge");
}

TEST(Repair, DoubleWallBetweenPartsBecomesOneWallWithSeams) {
  // Each cube closed, with its own facets on the common square and the vertices there welded:
  // the second copy of the square is a double wall, removed; its sides stay as seams.
  RawMesh m;
  AddCube(m, 0, 0, 0);
  AddCube(m, 1, 0, 0);
  RepairResult r = Repair(m);
  EXPECT_EQ(r.report.count(RepairKind::kWeldedVertex), 4u);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateFacet), 2u);
  EXPECT_EQ(r.report.count(RepairKind::kSeamEdge), 4u);
  EXPECT_EQ(m.num_faces(), 22u);
}

TEST(Repair, StrictModeNamesEveryDefectAndChangesNothing) {
  RawMesh m;
  AddCube(m, 0, 0, 0);
  AddCube(m, 1, 1, 1);
  for (size_t c = 36; c < 72; ++c)
    if (m.triangles[c] == 8) m.triangles[c] = 7;  // non-manifold vertex 7
  Flip(m, 3);
  Flip(m, 20);
  AppendFacet(m, {0, 1, 1});                                            // facet 24
  AppendFacet(m, {m.triangles[15], m.triangles[16], m.triangles[17]});  // facet 25 = 5
  const RawMesh before = m;
  RepairOptions strict;
  strict.mode = RepairMode::kOff;
  absl::StatusOr<RepairResult> r = RepairMesh(m, strict);
  ASSERT_FALSE(r.ok());
  ExpectSameMesh(m, before);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  const std::string message(r.status().message());
  EXPECT_HAS(message,
             "repair is off and the mesh has 5 defects (1 degenerate facet, "
             "1 duplicate facet, 2 flipped facets, 1 non-manifold vertex)");
  EXPECT_HAS(message, "degenerate facet 24 at (0.666666667, 0, 0): repeats a vertex");
  EXPECT_HAS(message, "duplicate facet 25 at");
  EXPECT_HAS(message, "flipped facet 3 at");
  EXPECT_HAS(message, "flipped facet 20 at");
  EXPECT_HAS(message, "non-manifold vertex 7 (facet 2) at (1, 1, 1)");

  // Seams are defects too; a mesh Build accepts passes, untouched.
  RawMesh seams = CubesSharingAFace();
  r = RepairMesh(seams, strict);
  ASSERT_FALSE(r.ok());
  EXPECT_HAS(std::string(r.status().message()), "4 non-manifold edges");
  RawMesh inside_out = CrackedCube(0);
  for (size_t f = 0; f < 12; ++f) Flip(inside_out, f);
  const RawMesh clean = inside_out;
  r = RepairMesh(inside_out, strict);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.num_changes(), 0u);
  ExpectSameMesh(inside_out, clean);
}

TEST(Repair, AFacetTurnedOverOntoItsNeighbourIsUnfolded) {
  RawMesh m = testing::CubeWithAFoldOnTop();
  const double volume = testing::SignedVolume(m);
  RepairResult r = Repair(m);
  EXPECT_EQ(r.report.count(RepairKind::kUnfoldedEdge), 1u) << r.report.Details();
  EXPECT_EQ(r.report.num_changes(), 1u) << r.report.Details();
  EXPECT_EQ(r.report.num_defects_left(), 0u) << r.report.Details();
  EXPECT_HAS(r.report.Summary(), "unfolded 1 folded edge (two facets lay on each other");
  EXPECT_HAS(Records(r.report, RepairKind::kUnfoldedEdge),
             "folded edge (facet 10) at (1, 1, 1): to (0, 0, 1): facets 10 and 11 lie on each "
             "other in their plane, one turned over: edge replaced by the other diagonal, "
             "(1, 0, 1) to (0.699999988, 0.300000012, 1)");
  // The fan as it was: every top facet faces up, the volume the same, nothing left to repair.
  ASSERT_EQ(m.num_faces(), 14u);
  for (size_t f = 10; f < 14; ++f) {
    const float* p[3];
    for (int k = 0; k < 3; ++k) p[k] = &m.positions[3 * m.triangles[3 * f + k]];
    const double up =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    EXPECT_GT(up, 0.0) << "facet " << f;
  }
  EXPECT_NEAR(testing::SignedVolume(m), volume, 1e-6);
  ExpectBuilds(m);
  RawMesh again = m;
  EXPECT_EQ(Repair(again).report.num_changes(), 0u);
}

TEST(Repair, AFoldAcrossFaceGroupsIsKeptAndReported) {
  RawMesh m = testing::CubeWithAFoldOnTop();
  NumberFacets(m);  // every facet its own group: the flip would move the groups' border
  const RawMesh before = m;
  RepairResult r = Repair(m);
  EXPECT_EQ(r.report.count(RepairKind::kUnfoldedEdge), 0u);
  // The turned-over facet lies on each of its three neighbours: three folded edges.
  EXPECT_EQ(r.report.count(RepairKind::kFoldLeft), 3u) << r.report.Details();
  EXPECT_HAS(r.report.Summary(), "no changes; left 3 folded edges as they were");
  EXPECT_HAS(Records(r.report, RepairKind::kFoldLeft),
             "fold left (facet 10) at (1, 1, 1): to (0, 0, 1): facets 10 and 11 lie on each other "
             "in their plane, one turned over; they belong to different face groups");
  ExpectSameMesh(m, before);
}

TEST(Repair, StrictModeRefusesAFold) {
  RawMesh m = testing::CubeWithAFoldOnTop();
  const RawMesh before = m;
  RepairOptions strict;
  strict.mode = RepairMode::kOff;
  absl::StatusOr<RepairResult> r = RepairMesh(m, strict);
  ASSERT_FALSE(r.ok());
  EXPECT_HAS(std::string(r.status().message()),
             "repair is off and the mesh has 3 defects (3 folded edges): folded edge (facet 10) at "
             "(1, 1, 1): to (0, 0, 1): facets 10 and 11 lie on each other in their plane, one "
             "turned over; folded edge (facet 11) at (1, 1, 1): to (0.699999988, 0.300000012, 1)");
  ExpectSameMesh(m, before);
}

TEST(Repair, AFanTurnedOverByAWeldIsUnfolded) {
  // A flat 4 x 4 square of 5 x 5 vertices (32 facets) with vertex 8 moved in to (2.5, 1.8), so
  // that the ring around the middle vertex 12 is not convex there; 12 then moved onto its
  // neighbour 6 = (1, 1) before the export: the weld joins them, the two facets of their edge
  // go, and the rest of 12's fan hangs from 6, which does not see all of it past 8: a facet
  // turned over.
  RawMesh m = testing::FlatGrid(4);
  m.positions[3 * 8] = 2.5f;
  m.positions[3 * 8 + 1] = 1.8f;
  for (int k = 0; k < 3; ++k) m.positions[3 * 12 + k] = m.positions[3 * 6 + k];
  RepairResult r = Repair(m);
  EXPECT_GT(r.report.count(RepairKind::kUnfoldedEdge), 0u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFoldLeft), 0u) << r.report.Details();
  // Unfolded: every facet faces up and together they cover the square once.
  double area = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const float* p[3];
    for (int k = 0; k < 3; ++k) p[k] = &m.positions[3 * m.triangles[3 * f + k]];
    const double up =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    EXPECT_GT(up, 0.0) << "facet " << f;
    area += up / 2;
  }
  EXPECT_NEAR(area, 16.0, 1e-5);
  ExpectBuilds(m);
}

TEST(Repair, StrictModeCapsTheListPerKind) {
  RawMesh m = testing::FlatGrid(10);  // 200 facets
  for (size_t f = 0; f < 60; f += 2) Flip(m, f);
  RepairOptions strict;
  strict.mode = RepairMode::kOff;
  strict.max_records_per_kind = 20;
  absl::StatusOr<RepairResult> r = RepairMesh(m, strict);
  ASSERT_FALSE(r.ok());
  const std::string message(r.status().message());
  EXPECT_HAS(message, "30 flipped facets");
  EXPECT_HAS(message, "flipped facet 38 at");
  EXPECT_HAS_NOT(message, "flipped facet 40 at");
  EXPECT_HAS(message, "and 10 more flipped facets");
  // Repaired, the grid takes the majority's orientation.
  RepairResult repaired = Repair(m);
  EXPECT_EQ(repaired.report.count(RepairKind::kFlippedFacet), 30u);
  EXPECT_EQ(m.triangles, testing::FlatGrid(10).triangles);
  EXPECT_HAS(repaired.report.Details(), "... and 10 more flipped facets");
}

TEST(Repair, UnrepairableInputIsRefusedWithEveryProblem) {
  RawMesh m = Cube();
  m.triangles[4] = 40;
  m.triangles[30] = 41;
  m.positions[3 * 6 + 1] = std::numeric_limits<float>::quiet_NaN();
  absl::StatusOr<RepairResult> r = RepairMesh(m, {});
  ASSERT_FALSE(r.ok());
  const std::string message(r.status().message());
  EXPECT_HAS(message, "3 unrepairable problems");
  EXPECT_HAS(message, "facet 1 references vertex 40 but the mesh has 8 vertices");
  EXPECT_HAS(message, "facet 10 references vertex 41");
  EXPECT_HAS(message, "vertex 6 (used by facet 0) has a non-finite coordinate");

  RawMesh cube = Cube();
  RepairOptions bad;
  bad.weld_tolerance = -1e-7;
  r = RepairMesh(cube, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_HAS(r.status().message(), "weld tolerance -1e-07: must be at least 0");

  RawMesh all_degenerate = {{0, 0, 0, 1, 0, 0, 2, 0, 0}, {0, 1, 2}, {}, {}};
  r = RepairMesh(all_degenerate, {});
  ASSERT_FALSE(r.ok());
  EXPECT_HAS(std::string(r.status().message()), "empty after repair");
  // Collinear points near the origin: nothing was rounded away, so no word of it.
  EXPECT_EQ(std::string(r.status().message()).find("far from the origin"), std::string::npos)
      << r.status().message();
}

// A part placed far from the origin for its size (an assembly's global coordinates) loses its
// detail to the 32-bit positions when it is read; where nothing is left, the error says why and
// what to do instead of only that every facet was degenerate.
TEST(Repair, EmptyBecauseRoundedAwayFarFromTheOrigin) {
  RawMesh far = testing::LoadTestMesh("fandisk.off");  // about 0.1 across
  for (size_t i = 0; i < far.positions.size(); ++i)
    if (i % 3 != 2) far.positions[i] += 1e7f;  // floats there are 1 apart
  for (const RepairMode mode : {RepairMode::kOn, RepairMode::kOff}) {
    RawMesh m = far;
    RepairOptions options;
    options.mode = mode;
    absl::StatusOr<RepairResult> r = RepairMesh(m, options);
    ASSERT_FALSE(r.ok());
    const std::string message(r.status().message());
    EXPECT_HAS(message, "empty after repair");
    EXPECT_HAS(message,
               "far from the origin for its size: its coordinates reach 1e+07, where "
               "32-bit floats (how femsimp keeps positions) are 1 apart");
    EXPECT_HAS(message, "translate the part near the origin");
  }
}

// Facets a CAD export dropped: a surface closed but for small holes is closed again.
TEST(Repair, MissingFacetsAreFilled) {
  RawMesh m = Cube();
  NumberFacets(m);
  const std::vector<uint32_t> gone(m.triangles.begin() + 3 * 8, m.triangles.begin() + 3 * 9);
  m.triangles.erase(m.triangles.begin() + 3 * 8, m.triangles.begin() + 3 * 9);  // facet 8
  m.face_groups.erase(m.face_groups.begin() + 8);
  m.face_fields[0].values.erase(m.face_fields[0].values.begin() + 8);
  RepairResult r = Repair(m);
  ExpectClosedCube(m);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  EXPECT_EQ(r.report.num_changes(), 1u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole),
             "filled hole next to facet 1 at (0.333333333, 0.666666667, 0): a hole of 3 edges "
             "(vertices 2, 0, 3) closed by 1 facet of area 0.5 (9.1% of its surface's), with "
             "facet 1's group and fields");
  // The new facet is the one dropped (0, 2, 3), turned as it was, appended with the group and
  // field value of the facet across the loop's first edge (2-0, facet 1).
  ASSERT_EQ(m.num_faces(), 12u);
  EXPECT_EQ(gone, (std::vector<uint32_t>{0, 2, 3}));
  EXPECT_EQ(std::vector<uint32_t>(m.triangles.end() - 3, m.triangles.end()),
            (std::vector<uint32_t>{3, 0, 2}));
  EXPECT_EQ(r.facet_origin.back(), 1u);
  EXPECT_EQ(m.face_groups.back(), 101);

  // Strict mode: an open surface is not a defect; nothing changes.
  RawMesh holed = Cube();
  holed.triangles.resize(3 * 11);
  ExpectStrictModeLeavesAlone(holed);
}

TEST(Repair, OpenSurfacesAreNotHoles) {
  // A flat square (its border is all of it) and a box without its lid (the opening is a fifth of
  // its area) stay open.
  RawMesh square;
  square.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  square.triangles = {0, 1, 2, 0, 2, 3};
  RawMesh tray = Cube();
  tray.triangles.resize(3 * 10);  // facets 10 and 11: the +z quad
  for (RawMesh* m : {&square, &tray}) {
    const int open = TopologyOf(*m).boundary_edges;
    const RawMesh before = *m;
    RepairResult r = Repair(*m);
    EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 0u) << r.report.Details();
    EXPECT_EQ(TopologyOf(*m).boundary_edges, open);
    // The tray's opening would close it with a fifth of its area: a face missing from a solid,
    // or a tray indeed; said, not filled. The square's border is the whole square (a sheet):
    // nothing to say.
    EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), m == &tray ? 1u : 0u) << r.report.Details();
    ExpectSameMesh(*m, before);
  }
  RepairResult r = Repair(tray);
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft),
             "a loop of 4 open edges (from vertex 4) left open: a fill would take at least 1 (20% "
             "of its surface's area), in one plane (a flat face missing?); larger than a few "
             "missing facets: the surface is not closed");
  EXPECT_HAS(r.report.Summary(), "no changes; left 1 hole open");
}

// A stray facet outside a solid and a leftover face inside it (CAD exports write such bits with
// the part) are removed: the part stays a closed solid. A sheet that is not small beside the
// solid, a small body with a face missing, a sheet part with no solid, and every piece with
// loose_piece_share 0 stay.
TEST(Repair, LoosePiecesBesideAClosedBodyAreRemoved) {
  RawMesh m;
  AddCube(m, 0, 0, 0, 10);  // area 600
  const RawMesh cube = m;
  const auto add_square = [](RawMesh& mesh, float x, float y, float z, float side) {
    const uint32_t b = static_cast<uint32_t>(mesh.num_vertices());
    mesh.positions.insert(mesh.positions.end(),
                          {x, y, z, x + side, y, z, x + side, y + side, z, x, y + side, z});
    mesh.triangles.insert(mesh.triangles.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
  };
  const uint32_t b = static_cast<uint32_t>(m.num_vertices());
  m.positions.insert(m.positions.end(), {20, 20, 20, 21, 20, 20, 20, 21, 20});
  AppendFacet(m, {b, b + 1, b + 2});  // facet 12, area 0.5
  add_square(m, 4, 4, 5, 2);          // facets 13 and 14 inside the cube, area 4
  RawMesh with_pieces = m;
  RepairResult r = Repair(m);
  ExpectSameMesh(m, cube);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kLoosePiece), 2u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kUnreferencedVertex), 7u);
  const std::string records = Records(r.report, RepairKind::kLoosePiece);
  EXPECT_HAS(records,
             "loose piece (facet 12) at (20.3333333, 20.3333333, 20): 1 facet of area 0.5 "
             "(0.083% of the bodies' area), open and joined to nothing: removed");
  EXPECT_HAS(records, "loose piece (facet 13) at (5, 5, 5): 2 facets of area 4 (0.67%");
  EXPECT_HAS(r.report.Summary(), "removed 2 loose pieces (open bits beside the bodies)");

  RepairOptions keep;
  keep.loose_piece_share = 0;
  RawMesh kept = with_pieces;
  EXPECT_EQ(Repair(kept, keep).report.count(RepairKind::kLoosePiece), 0u);
  EXPECT_EQ(kept.num_faces(), 15u);

  // A sheet of 1.5 % of the solid's area is part of the model; so is a small box without its
  // lid (what would close it is a fifth of its area: a face missing, not a sheet's border).
  RawMesh sheet = cube;
  add_square(sheet, 20, 0, 0, 3);
  RawMesh tray = cube;
  AddCube(tray, 20, 0, 0, 0.5);
  tray.triangles.resize(3 * 22);
  for (RawMesh* mesh : {&sheet, &tray}) {
    const size_t faces = mesh->num_faces();
    RepairResult left = Repair(*mesh);
    EXPECT_EQ(left.report.count(RepairKind::kLoosePiece), 0u) << left.report.Details();
    EXPECT_EQ(mesh->num_faces(), faces);
  }
  // A facet dangling from an edge of the solid (the edge then has three facets) comes off, and
  // the edge is the solid's again; two facets on one edge are not one dangling facet (the edge
  // keeps three facets without either) and stay, as a seam.
  const auto add_fin = [](RawMesh& mesh, uint32_t a, uint32_t b, std::array<float, 3> apex) {
    const uint32_t v = static_cast<uint32_t>(mesh.num_vertices());
    mesh.positions.insert(mesh.positions.end(), apex.begin(), apex.end());
    mesh.triangles.insert(mesh.triangles.end(), {a, b, v});
  };
  RawMesh fin = cube;
  add_fin(fin, 4, 5, {5, -0.5f, 10.5f});  // on the edge (0, 0, 10) - (10, 0, 10)
  r = Repair(fin);
  ExpectSameMesh(fin, cube);
  EXPECT_EQ(r.report.count(RepairKind::kSeamEdge), 0u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kLoosePiece),
             "loose piece (facet 12) at (5, -0.166666667, 10.1666667): 1 facet of area 3.54 "
             "(0.59% of the bodies' area), open and hanging from 1 edge of a body, which "
             "it made non-manifold: removed (a dangling facet;");
  // A facet missing too: the fin joined the solid to a sheet that is no hole, so the hole was
  // left open; once the fin is off, the hole is filled.
  RawMesh holed = cube;
  holed.triangles.erase(holed.triangles.begin() + 3 * 1, holed.triangles.begin() + 3 * 2);
  add_fin(holed, 4, 5, {5, -0.5f, 10.5f});
  r = Repair(holed);
  EXPECT_EQ(r.report.count(RepairKind::kLoosePiece), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), 0u) << r.report.Details();
  EXPECT_HAS_NOT(r.report.Details(), "hole left open");
  EXPECT_EQ(holed.num_faces(), 12u);
  EXPECT_EQ(TopologyOf(holed).boundary_edges, 0);
  ExpectBuilds(holed);
  // A cavity's wall faces into the cavity: the fin on the outer shell once made that shell a
  // seam's, not closed, so the cavity's wall counted as a body of its own and was turned out.
  RawMesh cavity = cube;
  AddCube(cavity, 4, 4, 4, 2);
  for (size_t f = 12; f < 24; ++f) Flip(cavity, f);
  add_fin(cavity, 4, 5, {5, -0.5f, 10.5f});
  r = Repair(cavity);
  EXPECT_EQ(r.report.count(RepairKind::kLoosePiece), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kReversedComponent), 0u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), 0u) << r.report.Details();
  EXPECT_NEAR(testing::SignedVolume(cavity), 1000 - 8, 1e-3);
  RawMesh fins = cube;
  add_fin(fins, 4, 5, {5, -0.5f, 10.5f});
  add_fin(fins, 5, 4, {5, -0.7f, 9.3f});
  EXPECT_EQ(Repair(fins).report.count(RepairKind::kLoosePiece), 0u);
  EXPECT_EQ(fins.num_faces(), 14u);

  // Without a closed body, a small sheet beside a large one is a sheet part's.
  RawMesh sheets;
  add_square(sheets, 0, 0, 0, 10);
  add_square(sheets, 20, 0, 0, 0.5);
  EXPECT_EQ(Repair(sheets).report.count(RepairKind::kLoosePiece), 0u);
  EXPECT_EQ(sheets.num_faces(), 4u);
}

// A closed body written twice (a part inserted twice at one place, or exported again and
// tessellated anew) comes off: the first copy stays, and the volume counts once. Bodies stacked
// on each other, a copy far away, a coating over a part (its cavity's wall between the two), a
// thin hollow body, and every copy with duplicate_body_offset 0 stay.
TEST(Repair, DuplicateBodiesAreRemoved) {
  const auto add_box = [](RawMesh& mesh, std::array<float, 3> at, std::array<float, 3> size) {
    const uint32_t b = static_cast<uint32_t>(mesh.num_vertices());
    AddCube(mesh, 0, 0, 0);
    for (uint32_t v = b; v < mesh.num_vertices(); ++v)
      for (int k = 0; k < 3; ++k)
        mesh.positions[3 * v + k] = at[k] + size[k] * mesh.positions[3 * v + k];
  };
  // The same cube with each face cut into four about its centre: another tessellation.
  const auto add_fan_cube = [](RawMesh& mesh, float at, float size) {
    RawMesh cube;
    AddCube(cube, at, at, at, size);
    for (uint32_t q = 0; q < 6; ++q) {
      const uint32_t* t = &cube.triangles[6 * q];
      const uint32_t ring[4] = {t[0], t[1], t[2], t[5]};
      const uint32_t c = static_cast<uint32_t>(cube.num_vertices());
      for (int k = 0; k < 3; ++k)
        cube.positions.push_back(
            0.5f * (cube.positions[3 * ring[0] + k] + cube.positions[3 * ring[2] + k]));
      for (int i = 0; i < 4; ++i)
        cube.triangles.insert(cube.triangles.end(), {ring[i], ring[(i + 1) % 4], c});
    }
    cube.triangles.erase(cube.triangles.begin(), cube.triangles.begin() + 36);
    const uint32_t b = static_cast<uint32_t>(mesh.num_vertices());
    mesh.positions.insert(mesh.positions.end(), cube.positions.begin(), cube.positions.end());
    for (uint32_t v : cube.triangles) mesh.triangles.push_back(b + v);
  };
  RawMesh cube;
  AddCube(cube, 0, 0, 0, 10);  // 2V/A = 3.33
  RawMesh twice = cube;
  add_box(twice, {0.0625f, 0.03125f, -0.015625f}, {10, 10, 10});
  RepairResult r = Repair(twice);
  ExpectSameMesh(twice, cube);
  ExpectBuilds(twice);
  EXPECT_EQ(r.report.num_changes(), 1u) << r.report.Details();  // its vertices go with it
  EXPECT_HAS(Records(r.report, RepairKind::kDuplicateBody),
             "duplicate body (facet 12) at (5.0625, 5.03125, 4.984375): closed body of 12 facets "
             "(volume 1000) repeats the body of 12 facets at facet 0: each lies within 0.0716 "
             "of the other (0.021 of its mean thickness 2V/A = 3.33); removed, the first kept");
  EXPECT_HAS(r.report.Summary(),
             "removed 1 duplicate body (closed bodies written twice; the first copy kept)");

  RawMesh retessellated = cube;
  add_fan_cube(retessellated, 0.1f, 10);
  add_fan_cube(retessellated, -0.1f, 10);  // a third copy
  r = Repair(retessellated);
  ExpectSameMesh(retessellated, cube);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateBody), 2u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kDuplicateBody),
             "closed body of 24 facets (volume 1000) repeats the body of 12 facets at facet 0");

  // A copy turned by 0.005 rad about the cube's edge on the z axis shares that edge (its two
  // facets there and the cube's make it a seam of four), and one of its facets on it is written
  // flipped: a shell closed by itself once its facets are turned alike, still a copy.
  RawMesh turned = cube;
  {
    RawMesh copy;
    AddCube(copy, 0, 0, 0, 10);
    const double c = std::cos(0.005), sn = std::sin(0.005);
    for (size_t v = 0; v < copy.num_vertices(); ++v) {
      const double x = copy.positions[3 * v], y = copy.positions[3 * v + 1];
      copy.positions[3 * v] = static_cast<float>(c * x - sn * y);
      copy.positions[3 * v + 1] = static_cast<float>(sn * x + c * y);
    }
    Flip(copy, 0);  // the -x quad's first facet, on the edge (0, 0, 0) - (0, 0, 10)
    const uint32_t b = static_cast<uint32_t>(turned.num_vertices());
    turned.positions.insert(turned.positions.end(), copy.positions.begin(), copy.positions.end());
    for (uint32_t v : copy.triangles) turned.triangles.push_back(b + v);
  }
  r = Repair(turned);
  ExpectSameMesh(turned, cube);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateBody), 1u) << r.report.Details();

  RepairOptions keep;
  keep.duplicate_body_offset = 0;
  RawMesh kept = cube;
  add_box(kept, {0.0625f, 0.03125f, -0.015625f}, {10, 10, 10});
  EXPECT_EQ(Repair(kept, keep).report.count(RepairKind::kDuplicateBody), 0u);
  EXPECT_EQ(kept.num_faces(), 24u);

  // A cube with a cavity, written twice: both of the copy's walls come off before the
  // orientation (with them the first cavity's wall lay inside two shells and faced outward),
  // and the part keeps its volume, 1000 - 216.
  RawMesh hollowed = cube;
  AddCube(hollowed, 2, 2, 2, 6);
  for (size_t f = 12; f < 24; ++f) Flip(hollowed, f);
  const RawMesh one = hollowed;
  const RawMesh copy = hollowed;
  {
    const uint32_t b = static_cast<uint32_t>(hollowed.num_vertices());
    for (size_t i = 0; i < copy.positions.size(); ++i)
      hollowed.positions.push_back(copy.positions[i] + (i % 3 == 0 ? 0.0625f : 0.03125f));
    for (uint32_t v : copy.triangles) hollowed.triangles.push_back(b + v);
  }
  r = Repair(hollowed);
  ExpectSameMesh(hollowed, one);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateBody), 2u) << r.report.Details();
  EXPECT_EQ(r.report.num_changes(), 2u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kDuplicateBody),
             "closed body of 12 facets (volume 216) repeats the body of 12 facets at facet 12");

  // Two plates of a laminate (0.2 thick, the second on the first, moved 0.01 along x so that no
  // vertex welds), a copy 20 away, and a shell 0.1 thick inside the cube (a thin hollow body:
  // the inner wall faces into the cavity) are no copies.
  RawMesh laminate, apart = cube, hollow = cube;
  add_box(laminate, {0, 0, 0}, {10, 10, 0.2f});
  add_box(laminate, {0.01f, 0, 0.2f}, {10, 10, 0.2f});
  AddCube(apart, 20, 0, 0, 10);
  RawMesh inner;
  AddCube(inner, 0.1f, 0.1f, 0.1f, 9.8f);
  for (size_t f = 0; f < inner.num_faces(); ++f) Flip(inner, f);
  {
    const uint32_t b = static_cast<uint32_t>(hollow.num_vertices());
    hollow.positions.insert(hollow.positions.end(), inner.positions.begin(), inner.positions.end());
    for (uint32_t v : inner.triangles) hollow.triangles.push_back(b + v);
  }
  for (RawMesh* mesh : {&laminate, &apart, &hollow}) {
    const RawMesh before = *mesh;
    r = Repair(*mesh);
    EXPECT_EQ(r.report.count(RepairKind::kDuplicateBody), 0u) << r.report.Details();
    ExpectSameMesh(*mesh, before);
  }
  // A coating over the cube, as a body of its own: its outer wall 0.05 out, its inner wall on
  // the cube's faces (moved by 0.001, so that it crosses them) facing into its cavity. The cube
  // and the inner wall lie within 0.002 of each other and cross, but the outer wall near both
  // repeats neither: layers, not copies.
  RawMesh coated = cube;
  add_box(coated, {-0.05f, -0.05f, -0.05f}, {10.1f, 10.1f, 10.1f});
  add_fan_cube(coated, 0.001f, 10);
  for (size_t f = 24; f < coated.num_faces(); ++f) Flip(coated, f);
  r = Repair(coated);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateBody), 0u) << r.report.Details();
  EXPECT_EQ(coated.num_faces(), 48u);
}

TEST(Repair, HolesTouchingAtAVertexAreToldApart) {
  // A cube without facets 9 (0, 3, 1) and 5 (0, 5, 4): two holes with vertex 0 in common, where
  // the facets left make two fans. Each hole is its own loop (across the gap at vertex 0, not
  // around a fan into the other hole) and gets its facet back.
  RawMesh touching = Cube();
  touching.triangles.erase(touching.triangles.begin() + 3 * 9, touching.triangles.begin() + 30);
  touching.triangles.erase(touching.triangles.begin() + 3 * 5, touching.triangles.begin() + 18);
  RepairResult r = Repair(touching);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 2u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kSplitVertex), 0u) << r.report.Details();
  EXPECT_EQ(TopologyOf(touching).boundary_edges, 0);
  ExpectBuilds(touching);
  EXPECT_NEAR(testing::SignedVolume(touching), 1.0, 1e-6);
  const std::string records = Records(r.report, RepairKind::kFilledHole);
  EXPECT_HAS(records, "a hole of 3 edges (vertices 0, 4, 5) closed by 1 facet");
  EXPECT_HAS(records, "a hole of 3 edges (vertices 1, 3, 0) closed by 1 facet");
}

TEST(Repair, FandiskHolesAreFilledAsMostFacetsAroundThemTurn) {
  const RawMesh clean = testing::LoadTestMesh("fandisk.off");
  RawMesh m = clean;
  // Facet 100 alone (a hole of 3 edges), and 5000 with the facet across its first edge (4).
  const uint32_t a = m.triangles[3 * 5000], b = m.triangles[3 * 5000 + 1];
  size_t across = 0;
  for (size_t f = 0; f < m.num_faces(); ++f)
    if (f != 5000 &&
        (m.triangles[3 * f] == b || m.triangles[3 * f + 1] == b || m.triangles[3 * f + 2] == b) &&
        (m.triangles[3 * f] == a || m.triangles[3 * f + 1] == a || m.triangles[3 * f + 2] == a))
      across = f;
  ASSERT_NE(across, 0u);
  std::vector<size_t> drop = {across, 5000, 100};
  std::sort(drop.rbegin(), drop.rend());
  for (size_t f : drop)
    m.triangles.erase(m.triangles.begin() + 3 * f, m.triangles.begin() + 3 * f + 3);
  Flip(m, 99);  // next to the first hole: turned by Orient, not followed by the fill
  EXPECT_GT(TopologyOf(m).boundary_edges, 0);
  RepairResult r = Repair(m);
  ExpectBuilds(m);
  EXPECT_EQ(TopologyOf(m).boundary_edges, 0);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 2u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), 1u) << r.report.Details();
  EXPECT_EQ(m.num_faces(), clean.num_faces());
  EXPECT_NEAR(testing::SignedVolume(m), testing::SignedVolume(clean),
              1e-4 * std::abs(testing::SignedVolume(clean)));
}

TEST(Repair, FandiskWithFlippedAndDuplicatedFacets) {
  const RawMesh clean = testing::LoadTestMesh("fandisk_groups_fields.ply");
  ASSERT_GT(clean.num_faces(), 10000u);
  ASSERT_FALSE(clean.face_groups.empty());
  RawMesh m = clean;
  for (size_t f : {100, 2000, 5000}) Flip(m, f);
  // Duplicates of facets 10 and 300 (the second turned over) inserted at 7000, then 500.
  const size_t dup[2] = {10, 300};
  const size_t at[2] = {500, 7000};
  for (int i = 1; i >= 0; --i) {
    std::vector<uint32_t> t(m.triangles.begin() + 3 * dup[i], m.triangles.begin() + 3 * dup[i] + 3);
    if (i == 1) std::swap(t[1], t[2]);
    m.triangles.insert(m.triangles.begin() + 3 * at[i], t.begin(), t.end());
    if (!m.face_groups.empty()) m.face_groups.insert(m.face_groups.begin() + at[i], 999 + i);
    for (FaceField& field : m.face_fields) field.values.insert(field.values.begin() + at[i], 1e6f);
  }
  EXPECT_FALSE(Mesh::Build(m).ok());
  RepairResult r = Repair(m);
  ExpectSameMesh(m, clean);
  ExpectBuilds(m);
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), 3u);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateFacet), 2u);
  EXPECT_EQ(r.report.num_changes(), 5u) << r.report.Details();
  // Input numbers: facets after 500 moved one on.
  const std::string flipped = Records(r.report, RepairKind::kFlippedFacet);
  EXPECT_HAS(flipped, "flipped facet 100 at");
  EXPECT_HAS(flipped, "flipped facet 2001 at");
  EXPECT_HAS(flipped, "flipped facet 5001 at");
  const std::string dups = Records(r.report, RepairKind::kDuplicateFacet);
  EXPECT_HAS(dups, "duplicate facet 500 at");
  EXPECT_HAS(dups, "same vertices as facet 10\n");
  EXPECT_HAS(dups, "duplicate facet 7001 at");
  EXPECT_HAS(dups, "same vertices as facet 300, opposite orientation");
}

// As an STL file would give it: three vertices per facet, a few facets flipped and repeated.
TEST(Repair, SoupOfFandiskIsWeldedBackDeterministically) {
  const RawMesh clean = testing::LoadTestMesh("fandisk.off");
  RawMesh soup;
  for (size_t f = 0; f < clean.num_faces(); ++f) {
    for (int i = 0; i < 3; ++i) {
      const float* p = &clean.positions[3 * clean.triangles[3 * f + i]];
      soup.positions.insert(soup.positions.end(), p, p + 3);
    }
    const uint32_t v = static_cast<uint32_t>(3 * f);
    if (f % 997 == 5) {
      AppendFacet(soup, {v, v + 2, v + 1});
    } else {
      AppendFacet(soup, {v, v + 1, v + 2});
    }
    if (f % 1999 == 7) AppendFacet(soup, {v + 1, v + 2, v});
  }
  RawMesh again = soup;
  RepairResult r = Repair(soup);
  ExpectBuilds(soup);
  EXPECT_EQ(CornerPoints(soup), CornerPoints(clean));
  const SoupTopology a = TopologyOf(soup), b = TopologyOf(clean);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_EQ(r.report.count(RepairKind::kWeldedVertex), 3 * clean.num_faces() - b.vertices);
  EXPECT_EQ(r.report.count(RepairKind::kFlippedFacet), (clean.num_faces() + 991) / 997);
  EXPECT_EQ(r.report.count(RepairKind::kDuplicateFacet), (clean.num_faces() + 1991) / 1999);
  Repair(again);
  ExpectSameMesh(again, soup);
}

// Timing on a large mesh, when FEMSIMP_REPAIR_BENCH names one (e.g. bench/data/blade_loop3.ply):
// as read, and as an STL-like soup (three vertices per facet) that the weld must join.
TEST(Repair, LargeMeshTiming) {
  const char* path = std::getenv("FEMSIMP_REPAIR_BENCH");
  if (path == nullptr) GTEST_SKIP() << "set FEMSIMP_REPAIR_BENCH to a mesh file to time";
  absl::StatusOr<RawMesh> read = ReadMeshFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  RawMesh soup;
  for (size_t c = 0; c < read->triangles.size(); ++c) {
    const float* p = &read->positions[3 * read->triangles[c]];
    soup.positions.insert(soup.positions.end(), p, p + 3);
    soup.triangles.push_back(static_cast<uint32_t>(c));
  }
  for (size_t f = 0; f < read->num_faces(); f += 100000) Flip(soup, f);
  for (RawMesh* m : {&*read, &soup}) {
    const size_t faces = m->num_faces(), vertices = m->num_vertices();
    const auto start = std::chrono::steady_clock::now();
    RepairResult r = Repair(*m);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("repair of %zu facets, %zu vertices: %.3f s\n%s\n", faces, vertices, s,
                r.report.Summary().c_str());
    ExpectBuilds(*m);
  }
}

// A Moebius strip: no choice of facet orientations is consistent. Repair leaves it and says so;
// PrepareMesh refuses it naming the component (the one kept defect Mesh::Build cannot take).
TEST(Repair, NonOrientableStripIsRefusedByName) {
  RawMesh strip;
  const int n = 24;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    for (const double s : {-0.3, 0.3}) {
      const double r = 1 + s * std::cos(t / 2);
      strip.positions.insert(strip.positions.end(), {float(r * std::cos(t)), float(r * std::sin(t)),
                                                     float(s * std::sin(t / 2))});
    }
  }
  for (int i = 0; i < n; ++i) {
    const uint32_t a = 2 * i, b = 2 * i + 1;
    // The last quad joins the first edge turned over: (a, b) meets (1, 0).
    const uint32_t c = i + 1 < n ? 2 * i + 2 : 1, d = i + 1 < n ? 2 * i + 3 : 0;
    strip.triangles.insert(strip.triangles.end(), {a, c, b, b, c, d});
  }
  RawMesh repaired = strip;
  absl::StatusOr<RepairResult> r = RepairMesh(repaired, RepairOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->report.count(RepairKind::kNonOrientable), 1u) << r->report.Details();
  EXPECT_TRUE(BlocksTheBuild(RepairKind::kNonOrientable));
  EXPECT_FALSE(BlocksTheBuild(RepairKind::kSeamEdge));
  EXPECT_FALSE(BlocksTheBuild(RepairKind::kContactLeft));
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(strip, RepairOptions{});
  ASSERT_FALSE(prepared.ok());
  EXPECT_EQ(prepared.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(prepared.status().message().find("defects no repair fixes: non-orientable component"),
            std::string::npos)
      << prepared.status();
}

}  // namespace
}  // namespace femsimp
