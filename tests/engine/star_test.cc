// The full-edge collapse's pieces (engine/star.h): the star of an edge, the optimal position,
// the deviation bound and the mass change, each checked against an independent computation on
// the whole mesh or against sampled distances.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "engine/deviation.h"
#include "engine/mechanics.h"
#include "engine/port.h"
#include "engine/star.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

struct Edge {
  Ring fan, target_fan;
  int target = 0;
};

// The star of vertex v and its first neighbour, read from the mesh.
Edge EdgeAt(Mesh& mesh, uint32_t v, int target = 0) {
  NativePort port(mesh);
  Edge e;
  EXPECT_EQ(GatherRing(port, v, e.fan), RingResult::kOk);
  e.target = target;
  EXPECT_EQ(GatherRing(port, e.fan.nbr[target], e.target_fan), RingResult::kOk);
  return e;
}

// The input with V and Vd merged at p: V's faces go to Vd, the two on V - Vd go away. Vertex
// ids are kept (V stays as an unused point, which the mass of the faces does not see).
RawMesh Collapsed(const RawMesh& in, uint32_t v, uint32_t vd, const DVec3& p) {
  RawMesh out = in;
  out.triangles.clear();
  for (size_t f = 0; f < in.num_faces(); ++f) {
    uint32_t t[3] = {in.triangles[3 * f], in.triangles[3 * f + 1], in.triangles[3 * f + 2]};
    const bool has_v = std::count(t, t + 3, v) > 0, has_vd = std::count(t, t + 3, vd) > 0;
    if (has_v && has_vd) continue;
    for (uint32_t& i : t)
      if (i == v) i = vd;
    out.triangles.insert(out.triangles.end(), t, t + 3);
  }
  out.positions[3 * vd] = static_cast<float>(p.x);
  out.positions[3 * vd + 1] = static_cast<float>(p.y);
  out.positions[3 * vd + 2] = static_cast<float>(p.z);
  return out;
}

MassProperties MassOf(const RawMesh& raw, bool closed, const DVec3& origin) {
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  return MeasureMass(*mesh, closed, origin);
}

DVec3 Rounded(const DVec3& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

// The largest distance from points sampled on one patch's triangles to the other patch.
double SampledDistance(const EdgeStar& star, bool from_old) {
  double worst = 0.0;
  constexpr int kSteps = 24;
  for (int k = 0; k < star.count; ++k) {
    if (!from_old && !star.survives[k]) continue;
    const DVec3 a = from_old ? star.a[k] : star.p;
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double s = double(i) / kSteps, t = double(j) / kSteps;
        const DVec3 q = a + s * (star.b[k] - a) + t * (star.c[k] - a);
        double nearest = 1e300;
        for (int g = 0; g < star.count; ++g) {
          if (from_old && !star.survives[g]) continue;
          nearest = std::min(nearest, testing::PointTriangleDistance(
                                          q, from_old ? star.p : star.a[g], star.b[g], star.c[g]));
        }
        worst = std::max(worst, nearest);
      }
  }
  return worst;
}

TEST(EdgeStar, HoldsBothFansOnce) {
  RawMesh raw = testing::MakeTorus(12, 8);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  const Edge e = EdgeAt(*mesh, 5);
  EdgeStar star;
  ASSERT_TRUE(star.Build(e.fan, e.target, e.target_fan));
  EXPECT_EQ(star.fan_faces, e.fan.faces);
  // Vd's fan less the two faces on V - Vd, which V's fan already holds.
  EXPECT_EQ(star.extra_faces(), e.target_fan.faces - 2);
  EXPECT_EQ(std::count(star.survives, star.survives + star.count, false), 2);
  EXPECT_EQ(star.vd_id, e.fan.nbr[e.target]);
  for (int k = 0; k < star.count; ++k)
    for (int l = k + 1; l < star.count; ++l) EXPECT_NE(star.face[k], star.face[l]);
  EXPECT_TRUE(star.Contains(star.v));
  EXPECT_TRUE(star.Contains(star.vd));
}

// The optimal point keeps the volume, and the star's mass change is the whole mesh's.
TEST(EdgeStar, MassChangeMatchesTheWholeMeshAndOptimalKeepsTheVolume) {
  const RawMesh raw = testing::MakeTorus(16, 10);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  const DVec3 origin{0.4, -0.3, 0.2};
  const MassProperties before = MassOf(raw, true, origin);
  for (uint32_t v : {3u, 40u, 77u}) {
    const Edge e = EdgeAt(*mesh, v, 1);
    EdgeStar star;
    ASSERT_TRUE(star.Build(e.fan, e.target, e.target_fan));
    for (const DVec3 p : {OptimalPosition(star), 0.5 * (star.v + star.vd), star.vd}) {
      star.p = Rounded(p);
      CollapseDelta delta;
      StarMassDelta(star, true, 1.0, 0, &delta);
      StarSecondMomentDelta(star, true, 1.0, origin, &delta);
      const MassProperties after = MassOf(Collapsed(raw, v, star.vd_id, star.p), true, origin);
      // The whole mesh's sums carry a few 1e-9 of its volume (measured: up to 2.6e-9 on this
      // torus), far below any budget.
      const double scale = std::fabs(before.measure);
      EXPECT_NEAR(delta.mass.measure, after.measure - before.measure, 5e-9 * scale);
      double direct = 0;  // the same change from the world origin, term by term
      for (int k = 0; k < star.count; ++k) {
        direct -= Dot(star.a[k], Cross(star.b[k], star.c[k])) / 6;
        if (star.survives[k]) direct += Dot(star.p, Cross(star.b[k], star.c[k])) / 6;
      }
      EXPECT_NEAR(delta.mass.measure, direct, 1e-12 * scale);
      EXPECT_NEAR(delta.mass.moment.x, after.moment.x - before.moment.x, 1e-8 * scale);
      EXPECT_NEAR(delta.mass.moment.z, after.moment.z - before.moment.z, 1e-8 * scale);
      EXPECT_NEAR(delta.mass.second.xx, after.second.xx - before.second.xx, 1e-8 * scale);
      EXPECT_NEAR(delta.mass.second.yz, after.second.yz - before.second.yz, 1e-8 * scale);
    }
    star.p = OptimalPosition(star);  // unrounded: the constraint holds exactly
    CollapseDelta delta;
    StarMassDelta(star, true, 1.0, 0, &delta);
    CollapseDelta half_edge;
    CollapseMassDelta(e.fan, e.target, true, 1.0, &half_edge);
    EXPECT_LT(std::fabs(delta.mass.measure), 1e-6 * std::fabs(half_edge.mass.measure) + 1e-15)
        << "vertex " << v;
  }
}

// Points moved onto the volume plane keep the volume under the star (the whole mesh's, by the
// mass delta checked above); a point already on it stays where it is.
TEST(EdgeStar, OntoVolumePlaneKeepsTheVolume) {
  const RawMesh raw = testing::MakeTorus(16, 10);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  for (uint32_t v : {3u, 40u, 77u}) {
    const Edge e = EdgeAt(*mesh, v, 1);
    EdgeStar star;
    ASSERT_TRUE(star.Build(e.fan, e.target, e.target_fan));
    CollapseDelta half_edge;
    CollapseMassDelta(e.fan, e.target, true, 1.0, &half_edge);
    const double spent = std::fabs(half_edge.mass.measure);
    ASSERT_GT(spent, 0.0);  // the torus bends: the half-edge collapse changes the volume
    for (const DVec3 p : {0.5 * (star.v + star.vd), star.LinkCentre(), star.vd, star.v}) {
      star.p = OntoVolumePlane(star, p);
      CollapseDelta delta;
      StarMassDelta(star, true, 1.0, 0, &delta);
      EXPECT_LT(std::fabs(delta.mass.measure), 1e-9 * spent) << "vertex " << v;
    }
    const DVec3 optimal = OptimalPosition(star);
    EXPECT_LT(Norm(OntoVolumePlane(star, optimal) - optimal), 1e-9 * Norm(star.vd - star.v));
  }
}

// Where the surface bends, the point that keeps the volume lies off the patch: outside the box
// of V, Vd and their one-rings on some stars. The star's box reaches that far, and is that box
// widened by WidenForPlacement, which the round scheduler widens the same way for each star of
// a candidate (its box must hold every point the collapse may place).
TEST(EdgeStar, PlacesBeyondThePatchWithinTheRoundsBox) {
  const RawMesh raw = testing::MakeTorus(16, 10);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  int beyond_patch = 0, outside_star = 0;
  for (uint32_t v = 0; v < mesh->vertex_capacity(); ++v) {
    for (int target = 0; target < 3; ++target) {
      const Edge e = EdgeAt(*mesh, v, target);
      DVec3 lo = ToD(e.fan.center_pos), hi = lo;  // V, its one-ring and Vd's
      const auto grow = [&](const Vec3& q) {
        lo = {std::min(lo.x, double(q.x)), std::min(lo.y, double(q.y)),
              std::min(lo.z, double(q.z))};
        hi = {std::max(hi.x, double(q.x)), std::max(hi.y, double(q.y)),
              std::max(hi.z, double(q.z))};
      };
      for (int r = 0; r < e.fan.neighbours(); ++r) grow(e.fan.pos[r]);
      for (int r = 0; r < e.target_fan.neighbours(); ++r) grow(e.target_fan.pos[r]);
      const DVec3 patch_lo = lo, patch_hi = hi;
      WidenForPlacement(&lo, &hi);
      EdgeStar star;
      ASSERT_TRUE(star.Build(e.fan, e.target, e.target_fan));
      EXPECT_TRUE(star.lo.x == lo.x && star.lo.y == lo.y && star.lo.z == lo.z &&
                  star.hi.x == hi.x && star.hi.y == hi.y && star.hi.z == hi.z)
          << "vertex " << v << " target " << target;
      const DVec3 p = OptimalPosition(star);
      beyond_patch += p.x < patch_lo.x || p.y < patch_lo.y || p.z < patch_lo.z ||
                      p.x > patch_hi.x || p.y > patch_hi.y || p.z > patch_hi.z;
      outside_star += !star.Contains(p);
    }
  }
  EXPECT_GT(beyond_patch, 0);
  EXPECT_LT(outside_star, beyond_patch);
}

// The bound holds: sampled distances between the two patches, both ways, stay below it (with
// a zero bound before); and on a flat patch nothing moves off the surface.
TEST(EdgeStar, DeviationBoundHoldsBothWays) {
  const RawMesh raw = testing::MakeTorus(16, 10);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  int bounded = 0;
  for (uint32_t v = 0; v < 160; v += 7) {
    for (int target = 0; target < 2; ++target) {
      const Edge e = EdgeAt(*mesh, v, target);
      EdgeStar star;
      ASSERT_TRUE(star.Build(e.fan, e.target, e.target_fan));
      for (const DVec3 p : {OptimalPosition(star), 0.5 * (star.v + star.vd)}) {
        star.p = Rounded(p);
        Displacement old_moved[kMaxStar], new_moved[kMaxStar];
        int work = 0;
        if (!BoundStarDeviation(star, old_moved, new_moved, &work)) continue;
        ++bounded;
        double bound = 0.0;
        for (int k = 0; k < star.count; ++k)
          if (star.survives[k]) bound = std::max(bound, new_moved[k].bound);
        EXPECT_LE(SampledDistance(star, true), bound * (1 + 1e-6)) << "vertex " << v;
        EXPECT_LE(SampledDistance(star, false), bound * (1 + 1e-6)) << "vertex " << v;
        EXPECT_GT(work, 0);
      }
    }
  }
  EXPECT_GT(bounded, 20) << "the torus's stars should mostly project without folds";
}

TEST(EdgeStar, FlatPatchStaysOnItsPlaneWithItsBound) {
  const RawMesh raw = testing::FlatGrid(6);
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  ASSERT_TRUE(mesh.ok());
  const uint32_t centre = 3 * 7 + 3;  // an interior vertex of the 7 x 7 points
  const Edge e = EdgeAt(*mesh, centre);
  EdgeStar star;
  ASSERT_TRUE(star.Build(e.fan, e.target, e.target_fan));
  star.p = OptimalPosition(star);
  EXPECT_NEAR(star.p.z, 0.0, 1e-12);
  const DVec3 mid = 0.5 * (star.v + star.vd);
  EXPECT_LT(Norm(star.p - mid), 1e-9) << "the pull decides where the quadric does not";
  // Points that had moved up to 0.01 straight up: moving within the plane adds nothing.
  Displacement old_moved[kMaxStar], new_moved[kMaxStar];
  for (Displacement& d : old_moved) {
    d.bound = 0.01;
    d.hi = {0, 0, 0.01};
  }
  int work = 0;
  ASSERT_TRUE(BoundStarDeviation(star, old_moved, new_moved, &work));
  for (int k = 0; k < star.count; ++k)
    if (star.survives[k]) {
      EXPECT_NEAR(new_moved[k].bound, 0.01, 1e-6);
      EXPECT_NEAR(new_moved[k].hi.z, 0.01, 1e-6);
      EXPECT_NEAR(new_moved[k].lo.z, 0.0, 1e-6);
    }
  // A point outside the link polygon cannot tile it.
  star.p = star.v + 10.0 * (star.vd - star.v);
  EXPECT_FALSE(BoundStarDeviation(star, old_moved, new_moved, &work));
}

double SegmentDistance(const DVec3& q, const DVec3& a, const DVec3& b) {
  const DVec3 d = b - a;
  const double t = std::clamp(Dot(q - a, d) / Dot(d, d), 0.0, 1.0);
  return Norm(q - (a + t * d));
}

// The largest distance from points sampled on polyline `from` to polyline `to`.
double PolylineDistance(const std::vector<DVec3>& from, const std::vector<DVec3>& to) {
  double worst = 0.0;
  for (size_t i = 0; i + 1 < from.size(); ++i)
    for (int s = 0; s <= 32; ++s) {
      const DVec3 q = from[i] + (s / 32.0) * (from[i + 1] - from[i]);
      double nearest = 1e300;
      for (size_t j = 0; j + 1 < to.size(); ++j)
        nearest = std::min(nearest, SegmentDistance(q, to[j], to[j + 1]));
      worst = std::max(worst, nearest);
    }
  return worst;
}

// The star of V = (3, 3) and Vd = (4, 3) of a 7 x 7 grid whose middle row (y = 3) is a feature
// line L - V - Vd - R, after `deform` moved the grid's points.
template <class Deform>
EdgeStar LineStar(Deform deform) {
  RawMesh raw = testing::FlatGrid(6);
  for (size_t i = 0; i < raw.positions.size(); i += 3) {
    DVec3 q{raw.positions[i], raw.positions[i + 1], raw.positions[i + 2]};
    deform(q);
    raw.positions[i] = static_cast<float>(q.x);
    raw.positions[i + 1] = static_cast<float>(q.y);
    raw.positions[i + 2] = static_cast<float>(q.z);
  }
  EdgeStar star;
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  EXPECT_TRUE(mesh.ok());
  if (!mesh.ok()) return star;
  const auto on_line = [&](uint32_t v) { return v / 7 == 3; };
  const auto mark_line = [&](Ring& fan) {
    for (int i = 0; i < fan.neighbours(); ++i)
      fan.feature[i] = on_line(fan.center) && on_line(fan.nbr[i]);
  };
  const uint32_t v = 3 * 7 + 3, vd = v + 1, l = v - 1;  // (3, 3), (4, 3), (2, 3)
  NativePort port(*mesh);
  Ring fan, target_fan;
  EXPECT_EQ(GatherRing(port, v, fan), RingResult::kOk);
  int target = -1, line_other = -1;
  for (int i = 0; i < fan.neighbours(); ++i) {
    if (fan.nbr[i] == vd) target = i;
    if (fan.nbr[i] == l) line_other = i;
  }
  EXPECT_GE(target, 0);
  EXPECT_GE(line_other, 0);
  if (target < 0 || line_other < 0) return star;
  EXPECT_EQ(GatherRing(port, vd, target_fan), RingResult::kOk);
  mark_line(fan);
  mark_line(target_fan);
  EXPECT_TRUE(star.Build(fan, target, target_fan, line_other));
  EXPECT_TRUE(star.on_line);
  EXPECT_EQ(star.line_vd_end.x, 5.0);
  return star;
}

// The largest bound of the star's new faces (BoundStarDeviation must lay the star out).
double StarBound(const EdgeStar& star) {
  Displacement old_moved[kMaxStar], new_moved[kMaxStar];
  int work = 0;
  EXPECT_TRUE(BoundStarDeviation(star, old_moved, new_moved, &work));
  double bound = 0.0;
  for (int k = 0; k < star.count; ++k)
    if (star.survives[k]) bound = std::max(bound, new_moved[k].bound);
  return bound;
}

// How far the old line L - V - Vd - R and the new one L - P - R are apart, the larger way.
double LineDistance(const EdgeStar& star) {
  const std::vector<DVec3> old_line = {star.line_v_end, star.v, star.vd, star.line_vd_end},
                           new_line = {star.line_v_end, star.p, star.line_vd_end};
  return std::max(PolylineDistance(old_line, new_line), PolylineDistance(new_line, old_line));
}

// V and Vd on a ridge curved in plan and in elevation (a feature line L - V - Vd - R) merge at the
// optimal point, off the line: the bound, with the old line laid onto L - P - R, holds the surface
// and the line both ways (sampled); without the line the same star lays out too.
TEST(EdgeStar, DeviationBoundHoldsAPlacedLine) {
  EdgeStar star = LineStar([](DVec3& q) {
    const double x = q.x - 3.0, y = q.y - 3.0;
    q.y += 0.1 * x * x;
    q.z = -std::fabs(y) - 0.08 * x * x;
  });
  ASSERT_TRUE(star.on_line);
  star.p = Rounded(OptimalPosition(star));
  EXPECT_GT(SegmentDistance(star.p, star.line_v_end, star.line_vd_end), 0.01)
      << "P should leave the chord";
  const double bound = StarBound(star);
  EXPECT_GT(bound, 0.0);
  EXPECT_LE(SampledDistance(star, true), bound * (1 + 1e-6));
  EXPECT_LE(SampledDistance(star, false), bound * (1 + 1e-6));
  EXPECT_LE(LineDistance(star), bound * (1 + 1e-6));
  star.on_line = false;  // the plain layout of the same star
  StarBound(star);
}

// A line curved in a flat patch (a face-group border in a plane): P moves the line but not the
// surface. Only a layout that puts the old line onto the new one makes the bound see the line's
// move; projected as it is, every point of the plane stays where it was and the bound is 0.
TEST(EdgeStar, DeviationBoundSeesALineMovedInItsPlane) {
  EdgeStar star = LineStar([](DVec3& q) { q.y += 0.1 * (q.x - 3.0) * (q.x - 3.0); });
  ASSERT_TRUE(star.on_line);
  star.p = 0.5 * (star.v + star.vd);  // in the plane, off the old line
  const double moved = LineDistance(star);
  EXPECT_GT(moved, 0.03);
  const double bound = StarBound(star);
  EXPECT_GE(bound, moved * (1 - 1e-6));
  EXPECT_LE(SampledDistance(star, true), bound * (1 + 1e-6));
  EXPECT_LE(SampledDistance(star, false), bound * (1 + 1e-6));
  star.on_line = false;
  EXPECT_LT(StarBound(star), 1e-3 * moved) << "a plain projection sees no move in a plane";
}

uint64_t Placed(const SimplifyResult& r) {
  uint64_t placed = 0;
  for (const PassStats& p : r.passes) placed += p.placed;
  return placed;
}

// Full-edge collapses run where a mass budget refuses a half-edge collapse, and never in a run
// with face fields (their transfer keeps resultants over V's fan only).
TEST(Placement, RescuesBudgetRefusalsButNotWithFaceFields) {
  SimplifyOptions o;
  o.threads = 2;
  o.tolerance_relative = 0.01;
  o.max_volume_change = 0.001;
  o.max_inertia_change = 0.005;
  o.placement = Placement::kOptimal;
  const RawMesh fandisk = testing::LoadTestMesh("fandisk.off");
  const testing::SimplifyRun placed = testing::SimplifyChecked(fandisk, o);
  EXPECT_GT(Placed(placed.result), 20u);  // 62 at the time of writing
  EXPECT_LE(std::fabs(placed.result.volume_change), 0.001);
  // Vertices off their input positions: some output point is no input point.
  std::vector<std::array<float, 3>> input_points;
  for (size_t v = 0; v < fandisk.num_vertices(); ++v)
    input_points.push_back(
        {fandisk.positions[3 * v], fandisk.positions[3 * v + 1], fandisk.positions[3 * v + 2]});
  std::sort(input_points.begin(), input_points.end());
  size_t moved = 0;
  for (size_t v = 0; v < placed.output.num_vertices(); ++v)
    moved += !std::binary_search(
        input_points.begin(), input_points.end(),
        std::array<float, 3>{placed.output.positions[3 * v], placed.output.positions[3 * v + 1],
                             placed.output.positions[3 * v + 2]});
  EXPECT_GT(moved, 0u);

  o.placement = Placement::kEndpoint;
  const testing::SimplifyRun endpoint = testing::SimplifyChecked(fandisk, o);
  EXPECT_EQ(Placed(endpoint.result), 0u);
  EXPECT_LT(placed.output.num_vertices(), endpoint.output.num_vertices());

  o.placement = Placement::kOptimal;
  const testing::SimplifyRun fields =
      testing::SimplifyChecked(testing::WithGroupsAndFields(fandisk), o);
  EXPECT_EQ(Placed(fields.result), 0u);
}

}  // namespace
}  // namespace femsimp
