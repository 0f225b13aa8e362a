// Openings in one plane: FillPlaneRegion's triangulation, and repair's HoleFill::kPlanar on
// solids with a flat face missing (engine/flat_openings.h).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "engine/mesh.h"
#include "engine/mesh_checks.h"
#include "engine/plane_fill.h"
#include "engine/repair.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

#define EXPECT_HAS(text, part)                               \
  EXPECT_NE(std::string(text).find(part), std::string::npos) \
      << "missing: " << (part) << "\nin: " << (text)

using Point = std::array<double, 3>;

Point Sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point Cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double Dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Sum of the triangles' areas, each signed by whether it turns counter-clockwise about `normal`.
double SignedArea(const std::vector<Point>& corners,
                  const std::vector<std::array<uint32_t, 3>>& triangles, const Point& normal) {
  double area = 0;
  for (const auto& t : triangles)
    area +=
        0.5 *
        Dot(Cross(Sub(corners[t[1]], corners[t[0]]), Sub(corners[t[2]], corners[t[0]])), normal) /
        std::sqrt(Dot(normal, normal));
  return area;
}

TEST(PlaneFill, FaceWithAHoleIsItsRingOnly) {
  const std::vector<std::vector<Point>> loops = {
      {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}},                   // the rim
      {{0.5, 0.5, 0}, {0.5, 1.5, 0}, {1.5, 1.5, 0}, {1.5, 0.5, 0}}};  // the hole, either winding
  const Point up = {0, 0, 1};
  absl::StatusOr<std::vector<std::array<uint32_t, 3>>> fill = FillPlaneRegion(loops, up);
  ASSERT_TRUE(fill.ok()) << fill.status();
  EXPECT_EQ(fill->size(), 8u);  // a ring of 8 corners
  std::vector<Point> corners = loops[0];
  corners.insert(corners.end(), loops[1].begin(), loops[1].end());
  // Every triangle counter-clockwise about +z: their signed areas sum to the ring's.
  EXPECT_NEAR(SignedArea(corners, *fill, up), 4.0 - 1.0, 1e-12);
  for (const auto& t : *fill)
    EXPECT_GT(Dot(Cross(Sub(corners[t[1]], corners[t[0]]), Sub(corners[t[2]], corners[t[0]])), up),
              0);
  // Seen from below, the same region turns the other way.
  fill = FillPlaneRegion(loops, {0, 0, -1});
  ASSERT_TRUE(fill.ok());
  EXPECT_NEAR(SignedArea(corners, *fill, {0, 0, -1}), 3.0, 1e-12);
}

TEST(PlaneFill, TiltedConvexPolygonGetsItsDelaunayTriangulation) {
  // 12 corners of an ellipse in a tilted plane: no corner inside another triangle's circle.
  const Point u = {0.6, 0.8, 0}, v = {-0.48, 0.36, 0.8}, centre = {10, -3, 7};
  std::vector<Point> loop;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * M_PI * i / 12, x = 3 * std::cos(a), y = std::sin(a);
    loop.push_back({centre[0] + x * u[0] + y * v[0], centre[1] + x * u[1] + y * v[1],
                    centre[2] + x * u[2] + y * v[2]});
  }
  const Point normal = Cross(u, v);
  absl::StatusOr<std::vector<std::array<uint32_t, 3>>> fill = FillPlaneRegion({loop}, normal);
  ASSERT_TRUE(fill.ok()) << fill.status();
  ASSERT_EQ(fill->size(), 10u);
  EXPECT_NEAR(SignedArea(loop, *fill, normal), 12 * 0.5 * 3 * std::sin(2 * M_PI / 12), 1e-9);
  for (const auto& t : *fill) {
    // The circumcentre in the plane: c = a + (|e|^2 (g x n) ... ) / (2 |n|^2), n = e x g.
    const Point a = loop[t[0]], e = Sub(loop[t[1]], a), g = Sub(loop[t[2]], a), n = Cross(e, g);
    const Point ge = Cross(n, e), gg = Cross(g, n);
    Point c;
    for (int k = 0; k < 3; ++k)
      c[k] = a[k] + (Dot(g, g) * ge[k] + Dot(e, e) * gg[k]) / (2 * Dot(n, n));
    const double r2 = Dot(Sub(a, c), Sub(a, c));
    for (uint32_t i = 0; i < loop.size(); ++i) {
      if (i != t[0] && i != t[1] && i != t[2]) {
        EXPECT_GE(Dot(Sub(loop[i], c), Sub(loop[i], c)), r2 * (1 - 1e-9)) << "corner " << i;
      }
    }
  }
}

TEST(PlaneFill, RefusesLoopsThatBoundNoRegion) {
  const Point up = {0, 0, 1};
  const auto why = [&](const std::vector<std::vector<Point>>& loops) {
    return std::string(FillPlaneRegion(loops, up).status().message());
  };
  EXPECT_HAS(why({{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}}), "cross each other");  // a bow tie
  EXPECT_HAS(why({{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}},
                  {{0.5, 0.5, 0}, {1.5, 0.5, 0}, {2, 2, 0}}}),
             "lie at one point");
  EXPECT_HAS(why({{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}},
                  {{1, 0, 0}, {1.5, 0.5, 0}, {0.5, 0.5, 0}}}),  // a corner on the rim's edge
             "runs through another corner");
  EXPECT_HAS(why({{{0, 0, 0}, {1, 0, 0}}}), "bounds no region");
}

// A box of `cells` per side, its six sides face groups 0 to 5 (-x, +x, -y, +y, -z, +z).
RawMesh GroupedBox(const std::array<double, 3>& size, const std::array<int, 3>& cells) {
  RawMesh box = testing::MakeBox(size, cells);
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      box.face_groups.insert(box.face_groups.end(),
                             2 * size_t(cells[(a + 1) % 3]) * size_t(cells[(a + 2) % 3]),
                             uint32_t(2 * a + side));
  return box;
}

// Drops the faces of group `group`.
void DropGroup(RawMesh& m, uint32_t group) {
  RawMesh out = m;
  out.triangles.clear();
  out.face_groups.clear();
  for (size_t f = 0; f < m.num_faces(); ++f)
    if (m.face_groups[f] != group) {
      out.triangles.insert(out.triangles.end(), &m.triangles[3 * f], &m.triangles[3 * f] + 3);
      out.face_groups.push_back(m.face_groups[f]);
    }
  m = std::move(out);
}

RepairResult RepairWith(RawMesh& m, HoleFill fill) {
  RepairOptions options;
  options.fill_holes = fill;
  absl::StatusOr<RepairResult> r = RepairMesh(m, options);
  EXPECT_TRUE(r.ok()) << r.status();
  return r.ok() ? *std::move(r) : RepairResult{};
}

std::string Records(const RepairReport& report, RepairKind kind) {
  std::string s;
  for (const RepairRecord& r : report.records)
    if (r.kind == kind) s += r.ToString() + "\n";
  return s;
}

void ExpectClosedSolid(const RawMesh& m, double volume) {
  EXPECT_EQ(TopologyOf(m).boundary_edges, 0);
  EXPECT_TRUE(Mesh::Build(m).ok());
  EXPECT_NEAR(testing::SignedVolume(m), volume, 1e-5 * volume);
}

TEST(RepairFillHoles, PlanarClosesASolidMissingAFlatFace) {
  RawMesh box = GroupedBox({3, 2, 1}, {3, 2, 2});
  DropGroup(box, 5);  // the top: a loop of 10 edges, a sixth of the area
  RawMesh plain = box;
  RepairResult r = RepairWith(plain, HoleFill::kSmall);
  EXPECT_EQ(TopologyOf(plain).boundary_edges, 10);
  EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), 1u);
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft), "--fill-holes planar fills a flat one");

  r = RepairWith(box, HoleFill::kPlanar);
  ExpectClosedSolid(box, 6.0);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), 0u) << r.report.Details();
  const std::string record = Records(r.report, RepairKind::kFilledHole);
  EXPECT_HAS(record, "an opening in one plane (10 edges in 1 loop,");
  EXPECT_HAS(record, "closed by 8 facets of area 6 ");
  EXPECT_HAS(record, "as new face group 5,");  // the groups left are 0 to 4
  EXPECT_HAS(record, "at an edge of the surface all round: a flat face missing");
  // The fill is a face of its own: group 5 on its 8 facets, the others as they were.
  size_t new_group = 0;
  for (size_t f = 0; f < box.num_faces(); ++f) {
    new_group += box.face_groups[f] == 5;
    if (box.face_groups[f] == 5) {
      for (int c = 0; c < 3; ++c) EXPECT_EQ(box.positions[3 * box.triangles[3 * f + c] + 2], 1.0f);
    }
  }
  EXPECT_EQ(new_group, 8u);
}

TEST(RepairFillHoles, FillTakesTheGroupOfTheFacetsAroundWhenThereIsOne) {
  RawMesh box = GroupedBox({1, 1, 1}, {2, 2, 2});
  for (uint32_t& g : box.face_groups) g = g == 5 ? 9 : 7;  // one body, its top apart
  DropGroup(box, 9);
  RepairResult r = RepairWith(box, HoleFill::kPlanar);
  ExpectClosedSolid(box, 1.0);
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole), "'s group and fields;");
  for (uint32_t g : box.face_groups) EXPECT_EQ(g, 7u);
}

// Point k of the boundary of the square [lo, hi]^2, counter-clockwise from its low corner, n
// edges a side.
std::array<float, 2> SquarePoint(int k, int n, float lo, float hi) {
  const int side = k / n % 4;
  const float t = float(k % n) / float(n), w = hi - lo;
  const float corner[4][2] = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}};
  const float dir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  return {corner[side][0] + t * w * dir[side][0], corner[side][1] + t * w * dir[side][1]};
}

// A square frame 3 x 3 x 1 around a 1 x 1 hole, facing out, each square `n` edges a side; its
// faces are groups 0 (top), 1 (bottom), 2 (outer walls), 3 (the hole's walls); volume 8.
RawMesh Frame(int n) {
  RawMesh m;
  const int ring = 4 * n;
  const auto along = [&](int k, float lo, float hi) { return SquarePoint(k, n, lo, hi); };
  for (float z : {0.0f, 1.0f})
    for (const auto& [lo, hi] : {std::pair(0.0f, 3.0f), std::pair(1.0f, 2.0f)})
      for (int k = 0; k < ring; ++k) {
        const std::array<float, 2> p = along(k, lo, hi);
        m.positions.insert(m.positions.end(), {p[0], p[1], z});
      }
  const auto o = [&](int k, int z) { return uint32_t(2 * ring * z + k % ring); };
  const auto i = [&](int k, int z) { return uint32_t(2 * ring * z + ring + k % ring); };
  const auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d, uint32_t group) {
    m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    m.face_groups.insert(m.face_groups.end(), {group, group});
  };
  for (int k = 0; k < ring; ++k) {
    quad(o(k, 1), o(k + 1, 1), i(k + 1, 1), i(k, 1), 0);  // top ring
    quad(o(k + 1, 0), o(k, 0), i(k, 0), i(k + 1, 0), 1);  // bottom ring
    quad(o(k, 0), o(k + 1, 0), o(k + 1, 1), o(k, 1), 2);  // outer walls
    quad(i(k + 1, 0), i(k, 0), i(k, 1), i(k + 1, 1), 3);  // the hole's walls
  }
  return m;
}

TEST(RepairFillHoles, AFaceWithAHoleIsFilledAsARing) {
  RawMesh frame = Frame(1);
  ExpectClosedSolid(frame, 8.0);
  DropGroup(frame, 0);  // two loops in one plane: filled apart, they would cover the hole
  RepairResult r = RepairWith(frame, HoleFill::kPlanar);
  ExpectClosedSolid(frame, 8.0);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole), "(8 edges in 2 loops,");
}

// A stepped block: 3 x 3 x 1 with a 1 x 1 x 1 block on its middle, each square `n` edges a side;
// the step's ring face (z = 1) is group 0, the rest group 1; volume 10.
RawMesh Step(int n) {
  RawMesh m;
  const int ring = 4 * n;
  const auto along = [&](int k, float lo, float hi) { return SquarePoint(k, n, lo, hi); };
  // Rings of the boundary: 0 the base (z 0, outer), 1 the step's rim (z 1, outer), 2 the block's
  // foot (z 1, inner), 3 its top (z 2, inner); then the centres of the base and the top.
  const float rings[4][3] = {{0, 3, 0}, {0, 3, 1}, {1, 2, 1}, {1, 2, 2}};
  for (const auto& r : rings)
    for (int k = 0; k < ring; ++k) {
      const std::array<float, 2> p = along(k, r[0], r[1]);
      m.positions.insert(m.positions.end(), {p[0], p[1], r[2]});
    }
  m.positions.insert(m.positions.end(), {1.5f, 1.5f, 0.0f, 1.5f, 1.5f, 2.0f});
  const uint32_t base = uint32_t(4 * ring), top = base + 1;
  const auto v = [&](int r, int k) { return uint32_t(r * ring + k % ring); };
  const auto tri = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t group) {
    m.triangles.insert(m.triangles.end(), {a, b, c});
    m.face_groups.push_back(group);
  };
  const auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d, uint32_t group) {
    tri(a, b, c, group);
    tri(a, c, d, group);
  };
  for (int k = 0; k < ring; ++k) {
    tri(base, v(0, k + 1), v(0, k), 1);                   // the base, facing down
    quad(v(0, k), v(0, k + 1), v(1, k + 1), v(1, k), 1);  // outer walls
    quad(v(1, k), v(1, k + 1), v(2, k + 1), v(2, k), 0);  // the step's ring
    quad(v(2, k), v(2, k + 1), v(3, k + 1), v(3, k), 1);  // the block's walls
    tri(top, v(3, k), v(3, k + 1), 1);                    // its top
  }
  return m;
}

TEST(RepairFillHoles, AFaceWhoseLossSplitTheSurfaceJoinsItAgain) {
  RawMesh step = Step(2);
  ExpectClosedSolid(step, 10.0);
  DropGroup(step, 0);  // two surfaces now: the base block open at its rim, the block at its foot
  EXPECT_EQ(TopologyOf(step).components, 2);
  RepairResult r = RepairWith(step, HoleFill::kPlanar);
  ExpectClosedSolid(step, 10.0);
  EXPECT_EQ(TopologyOf(step).components, 1);  // one solid again, not two touching at z = 1
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  const std::string record = Records(r.report, RepairKind::kFilledHole);
  EXPECT_HAS(record, "(16 edges in 2 loops,");
  EXPECT_HAS(record, "closed by 16 facets of area 8 ");
}

TEST(RepairFillHoles, AFacetDroppedBesideTheFaceIsANotch) {
  // The top of a 3 x 2 x 1 box dropped, and one facet of the +x side at the top edge too: the
  // loop leaves the top's plane at that facet's lower corner. The notch gets its facet back and
  // the top its fill.
  RawMesh box = GroupedBox({3, 2, 1}, {3, 2, 2});
  DropGroup(box, 5);
  // The +x side (group 1) is the second block of 2 * 2 * 2 facets; the one with two corners on
  // the top edge.
  size_t notch = box.num_faces();
  for (size_t f = 8; f < 16 && notch == box.num_faces(); ++f) {
    int top = 0;
    for (int c = 0; c < 3; ++c) top += box.positions[3 * box.triangles[3 * f + c] + 2] == 1.0f;
    if (top == 2) notch = f;
  }
  ASSERT_LT(notch, box.num_faces());
  box.triangles.erase(box.triangles.begin() + 3 * notch, box.triangles.begin() + 3 * notch + 3);
  box.face_groups.erase(box.face_groups.begin() + notch);
  RepairResult r = RepairWith(box, HoleFill::kPlanar);
  ExpectClosedSolid(box, 6.0);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole),
             "(11 edges in 1 loop, from vertex 5) closed by 9 facets (1 of them closing notches "
             "off its plane) of area 6.25 ");
  // The notch's facet is the side's again (group 1), the top's 8 a new face (group 5).
  size_t side = 0, top = 0;
  for (uint32_t g : box.face_groups) {
    side += g == 1;
    top += g == 5;
  }
  EXPECT_EQ(side, 8u);
  EXPECT_EQ(top, 8u);
}

TEST(RepairFillHoles, AHoleThroughAFlatFaceIsClosedAndSaidSo) {
  RawMesh frame = Frame(2);
  ExpectClosedSolid(frame, 8.0);
  DropGroup(frame, 3);  // the hole's walls: its rims (8 edges) lie flush in the top and bottom
  RepairResult r = RepairWith(frame, HoleFill::kPlanar);
  ExpectClosedSolid(frame, 9.0);  // a block: what a plain fill of flat openings makes of it
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 2u) << r.report.Details();
  EXPECT_HAS(Records(r.report, RepairKind::kFilledHole),
             "flush with the facets around it: a hole through a flat face, closed (was it meant "
             "to be open?)");
}

TEST(RepairFillHoles, WhatIsNotAFlatFaceStaysOpen) {
  // A box without its top and one side: one loop of 12 edges, bent, whose corners off either
  // plane are more than a notch.
  RawMesh bent = GroupedBox({1, 1, 1}, {2, 2, 2});
  DropGroup(bent, 5);
  DropGroup(bent, 1);
  RepairResult r = RepairWith(bent, HoleFill::kPlanar);
  EXPECT_EQ(TopologyOf(bent).boundary_edges, 12);
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft), "not in one plane;");
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft), "is not in one plane");
  // With one cell a side its 6 corners have a plane through 4 (the box's diagonal), leaving two
  // notches that would close onto the sides: refused as folds.
  RawMesh diagonal = GroupedBox({1, 1, 1}, {1, 1, 1});
  DropGroup(diagonal, 5);
  DropGroup(diagonal, 1);
  r = RepairWith(diagonal, HoleFill::kPlanar);
  EXPECT_EQ(TopologyOf(diagonal).boundary_edges, 6);
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft), "a fill would fold onto the surface");

  // A sheet: its border spans all of it.
  RawMesh sheet = testing::FlatGrid(4);
  r = RepairWith(sheet, HoleFill::kPlanar);
  EXPECT_EQ(r.report.num_changes(), 0u) << r.report.Details();
  EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), 0u);

  // A tray with a block standing up through its opening: a lid would cut the block.
  RawMesh tray = GroupedBox({3, 3, 1}, {3, 3, 1});
  DropGroup(tray, 5);
  testing::Append(tray, testing::MakeBox({1, 1, 1}, {1, 1, 1}), {1, 1, 0.5f});
  tray.face_groups.resize(tray.num_faces(), 8);
  r = RepairWith(tray, HoleFill::kPlanar);
  EXPECT_EQ(TopologyOf(tray).boundary_edges, 12);
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft), "a fill would cross the surface");
}

TEST(RepairFillHoles, LooseFacetsAreNotOpenings) {
  // 20,000 facets welded to nothing, as a soup exported without shared vertices: each is a
  // surface whose border is all of it, in its own plane. None is filled, and the planar mode
  // does not try them against each other (that would be 4e8 plane tests).
  RawMesh soup;
  for (uint32_t i = 0; i < 20000; ++i) {
    const float x = float(i % 200) * 3, y = float(i / 200) * 3;
    soup.positions.insert(soup.positions.end(), {x, y, 0, x + 1, y, 0, x, y + 1, 0.5f});
    soup.triangles.insert(soup.triangles.end(), {3 * i, 3 * i + 1, 3 * i + 2});
  }
  RepairResult r = RepairWith(soup, HoleFill::kPlanar);
  EXPECT_EQ(r.report.num_changes(), 0u) << r.report.Summary();
  EXPECT_EQ(r.report.count(RepairKind::kHoleLeft), 0u);
  EXPECT_EQ(soup.num_faces(), 20000u);
}

TEST(RepairFillHoles, NoneLeavesEvenASmallHole) {
  RawMesh cube = GroupedBox({1, 1, 1}, {2, 2, 2});
  cube.triangles.resize(cube.triangles.size() - 3);  // a facet missing
  cube.face_groups.pop_back();
  RawMesh small = cube;
  RepairResult r = RepairWith(small, HoleFill::kSmall);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 1u);
  r = RepairWith(cube, HoleFill::kNone);
  EXPECT_EQ(TopologyOf(cube).boundary_edges, 3);
  EXPECT_EQ(r.report.count(RepairKind::kFilledHole), 0u);
  EXPECT_HAS(Records(r.report, RepairKind::kHoleLeft), "hole filling is off (fill_holes none)");
}

}  // namespace
}  // namespace femsimp
