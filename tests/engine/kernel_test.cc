// Single collapses through the removal kernel, checked one at a time.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/features.h"
#include "engine/kernel.h"
#include "engine/mesh_checks.h"
#include "engine/port.h"
#include "engine/quadric.h"
#include "engine/vec.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

struct Harness {
  explicit Harness(const RawMesh& raw, SimplifyOptions options = {})
      : mesh(*Mesh::Build(raw)), port(mesh), rules(RulesFor(options)) {
    budget.alive = static_cast<int64_t>(mesh.CountLiveVertices());
    MarkFeatures(mesh, options.feature_angle_deg);
  }
  static RuleSet RulesFor(const SimplifyOptions& options) {
    RuleSetup setup;
    setup.cos_feature = std::cos(options.feature_angle_deg * std::numbers::pi / 180.0);
    return RuleSet::Build(options, setup);
  }
  Outcome Remove(uint32_t v, bool requeue_changed = false) {
    RemovalKernel<NativePort> kernel(port, rules, /*quadric=*/false, budget, stats,
                                     /*placement=*/false, requeue_changed);
    return kernel.TryRemove(v);
  }
  uint32_t Status(uint32_t v) const { return mesh.status()[v].load(); }
  Mesh mesh;
  NativePort port;
  RuleSet rules;
  RemovalBudget budget;
  KernelStats stats;
};

void ExpectSameTopology(const RawMesh& before, const Mesh& mesh) {
  ASSERT_EQ(HalfEdgeInvariantViolation(mesh), "");
  const RawMesh after = mesh.ToRaw();
  ASSERT_TRUE(Mesh::Build(after).ok()) << Mesh::Build(after).status();
  const auto a = TopologyOf(before), b = TopologyOf(after);
  EXPECT_EQ(a.euler(), b.euler());
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(a.boundary_edges == 0, b.boundary_edges == 0);
}

TEST(Kernel, InteriorCollapseOnFlatGrid) {
  const RawMesh raw = testing::FlatGrid(4);
  Harness h(raw);
  const uint32_t center = 2 * 5 + 2;
  ASSERT_EQ(h.Remove(center), Outcome::kRemoved);
  EXPECT_TRUE(h.mesh.IsRemoved(center));
  EXPECT_EQ(h.mesh.CountLiveFaces(), 32u - 2u);
  ExpectSameTopology(raw, h.mesh);
  // The status words of the one-ring are unlocked again.
  for (uint32_t v = 0; v < h.mesh.vertex_capacity(); ++v)
    EXPECT_EQ(h.mesh.status()[v].load() & kLockedBit, 0u);
}

TEST(Kernel, BoundaryVertexCollapsesAlongItsBoundary) {
  const RawMesh raw = testing::FlatGrid(4);
  Harness h(raw);
  const uint32_t on_edge = 2;  // middle of the bottom row
  ASSERT_EQ(h.Remove(on_edge), Outcome::kRemoved);
  ExpectSameTopology(raw, h.mesh);
  const auto after = TopologyOf(h.mesh.ToRaw());
  EXPECT_EQ(after.boundary_edges, TopologyOf(raw).boundary_edges - 1);
  // The bottom row stays straight: no surviving vertex left the boundary line y = 0.
  const RawMesh out = h.mesh.ToRaw();
  int bottom = 0;
  for (size_t v = 0; v < out.num_vertices(); ++v) bottom += out.positions[3 * v + 1] == 0.f;
  EXPECT_EQ(bottom, 4);
}

TEST(Kernel, EveryVertexOfAGridOnceInTopologyOnlyMode) {
  SimplifyOptions topology;
  topology.topology_only = true;
  topology.feature_angle_deg = 180;  // every edge of these solids is sharp: no corners here
  const RawMesh raw = testing::FlatGrid(6);
  Harness h(raw, topology);
  int removed = 0;
  for (uint32_t v = 0; v < h.mesh.vertex_capacity(); ++v) {
    removed += h.Remove(v) == Outcome::kRemoved;
    ASSERT_EQ(HalfEdgeInvariantViolation(h.mesh), "") << "after vertex " << v;
  }
  EXPECT_GT(removed, 20);
  ExpectSameTopology(raw, h.mesh);
}

// A collapse that deletes a face on the boundary makes the edge joined across it a boundary
// edge: it must become a feature edge as boundaries are, or the boundary vertices at its ends
// would count one feature edge and be taken for corners (never moved again).
TEST(Kernel, EdgesThatBecomeBoundaryAreFeatures) {
  SimplifyOptions topology;
  topology.topology_only = true;
  const RawMesh raw = testing::FlatGrid(6);
  Harness h(raw, topology);
  for (uint32_t v = 0; v < h.mesh.vertex_capacity(); ++v) h.Remove(v);
  ASSERT_EQ(HalfEdgeInvariantViolation(h.mesh), "");
  int boundary = 0;
  const HalfEdgeQ* e = h.mesh.halfedges();
  for (uint32_t i = 0; i < h.mesh.halfedge_capacity(); ++i) {
    if ((e[i].flags & kFaceRemoved) || e[i].twin != kNone) continue;
    ++boundary;
    EXPECT_TRUE(e[i].flags & kFeatureEdge) << "boundary half-edge " << i;
  }
  EXPECT_GT(boundary, 0);
  EXPECT_LT(boundary, 24);  // some boundary collapses happened
}

TEST(Kernel, TetrahedronAndSingleTriangleAreNeverCollapsed) {
  SimplifyOptions topology;
  topology.topology_only = true;
  topology.feature_angle_deg = 180;  // every edge of these solids is sharp: no corners here
  for (const RawMesh& raw : {testing::Tetrahedron(), testing::SingleTriangle()}) {
    Harness h(raw, topology);
    for (uint32_t v = 0; v < h.mesh.vertex_capacity(); ++v)
      EXPECT_EQ(h.Remove(v), Outcome::kRejected);
    EXPECT_GT(h.stats.rejections[static_cast<int>(Reject::kValence)], 0u);
    EXPECT_EQ(h.mesh.CountLiveVertices(), raw.num_vertices());
  }
}

TEST(Kernel, OctahedronShrinksToATetrahedronAndStops) {
  SimplifyOptions topology;
  topology.topology_only = true;
  topology.feature_angle_deg = 180;  // every edge of these solids is sharp: no corners here
  const RawMesh raw = testing::Octahedron();
  Harness h(raw, topology);
  for (int round = 0; round < 3; ++round)
    for (uint32_t v = 0; v < 6; ++v) {
      if (h.mesh.IsRemoved(v)) continue;
      h.mesh.status()[v].store(kRemovable);
      h.Remove(v);
      ASSERT_EQ(HalfEdgeInvariantViolation(h.mesh), "");
    }
  EXPECT_EQ(h.mesh.CountLiveVertices(), 4u);
  EXPECT_EQ(h.mesh.CountLiveFaces(), 4u);
  ExpectSameTopology(raw, h.mesh);
}

TEST(Kernel, LockedNeighbourIsAConflict) {
  const RawMesh raw = testing::FlatGrid(4);
  Harness h(raw);
  const uint32_t center = 12, neighbour = 13;
  h.mesh.status()[neighbour].store(kRemovable | kLockedBit);
  EXPECT_EQ(h.Remove(center), Outcome::kConflict);
  EXPECT_EQ(h.stats.lock_conflicts, 1u);
  EXPECT_EQ(h.mesh.status()[center].load(), kRemovable);  // V unlocked, still a candidate
  EXPECT_EQ(h.mesh.CountLiveVertices(), 25u);
}

// Every collapse on fandisk, one at a time: each new triangle keeps all angles above the
// minimum and its normal within the deviation of the triangle it replaces; the link condition
// and valence checks fire; the structure stays valid throughout.
TEST(Kernel, EachCollapseOnFandiskMeetsTheCriteria) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  ASSERT_GT(raw.num_faces(), 0u);
  SimplifyOptions paper;  // 25 degrees, 10 degrees
  Harness h(raw, paper);
  const double cos_dev = std::cos(25.0 * std::numbers::pi / 180.0) - 1e-9;
  int removed = 0;
  for (int round = 0; round < 3; ++round) {
    for (uint32_t v = 0; v < h.mesh.vertex_capacity(); ++v) {
      if (h.mesh.IsRemoved(v)) continue;
      Ring before;
      NativePort port(h.mesh);
      ASSERT_EQ(GatherRing(port, v, before), RingResult::kOk);
      h.mesh.status()[v].store(kRemovable);
      if (h.Remove(v) != Outcome::kRemoved) continue;
      ++removed;
      const HalfEdgeQ* he = h.mesh.halfedges();
      const VertexQ* vx = h.mesh.vertices();
      for (int i = 0; i < before.faces; ++i) {
        const uint32_t f = FaceOf(before.out[i]);
        if (h.mesh.IsFaceRemoved(f)) continue;
        RawMesh tri;
        for (int k = 0; k < 3; ++k) {
          const VertexQ& p = vx[he[3 * f + k].target];
          tri.positions.insert(tri.positions.end(), {p.x, p.y, p.z});
        }
        tri.triangles = {0, 1, 2};
        EXPECT_GE(testing::MinAngleDegrees(tri, 0), 10.0 - 1e-4);
        // Old triangle: the same face slot with V in place of the new vertex.
        const Vec3& b = before.pos[i];
        const Vec3& c = before.pos[(i + 1) % before.neighbours()];
        const Vec3& a = before.center_pos;
        auto normal = [](Vec3 p, Vec3 q, Vec3 r) {
          double u[3] = {q.x - p.x, q.y - p.y, q.z - p.z}, w[3] = {r.x - p.x, r.y - p.y, r.z - p.z};
          return std::array<double, 3>{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                       u[0] * w[1] - u[1] * w[0]};
        };
        const auto n_old = normal(a, b, c);
        const Vec3 t0{tri.positions[0], tri.positions[1], tri.positions[2]};
        const Vec3 t1{tri.positions[3], tri.positions[4], tri.positions[5]};
        const Vec3 t2{tri.positions[6], tri.positions[7], tri.positions[8]};
        const auto n_new = normal(t0, t1, t2);
        const double dot = n_old[0] * n_new[0] + n_old[1] * n_new[1] + n_old[2] * n_new[2];
        const double len =
            std::sqrt((n_old[0] * n_old[0] + n_old[1] * n_old[1] + n_old[2] * n_old[2]) *
                      (n_new[0] * n_new[0] + n_new[1] * n_new[1] + n_new[2] * n_new[2]));
        EXPECT_GE(dot / len, cos_dev) << "face " << f << " after removing " << v;
      }
      if (removed % 16 == 0) {
        ASSERT_EQ(HalfEdgeInvariantViolation(h.mesh), "");
      }
    }
  }
  EXPECT_GT(removed, 3000);
  EXPECT_GT(h.stats.rejections[static_cast<int>(Reject::kNormalDeviation)], 0u);
  EXPECT_GT(h.stats.rejections[static_cast<int>(Reject::kMinAngle)], 0u);
  ExpectSameTopology(raw, h.mesh);
}

// With the quadric cost the shape rules and the bound's screen run only on the directions tried,
// the screen first once it has refused one the shape rules passed (CheckFan): every collapse
// still meets the shape criteria and keeps each surviving face's bound within the tolerance, and
// both kinds of rule refuse.
TEST(Kernel, TheQuadricOrderRunsEveryFanRuleOnTheDirectionItTakes) {
  const RawMesh raw = testing::LoadTestMesh("fandisk.off");
  ASSERT_GT(raw.num_faces(), 0u);
  SimplifyOptions paper;  // 25 degrees, 10 degrees
  Mesh mesh = *Mesh::Build(raw);
  MarkFeatures(mesh, paper.feature_angle_deg);
  mesh.EnsureFaceAttrs();
  InitQuadrics(mesh);
  RuleSetup setup;
  setup.cos_feature = std::cos(paper.feature_angle_deg * std::numbers::pi / 180.0);
  setup.tolerance = 0.02f;  // fandisk's diagonal is about 7: a tolerance that refuses often
  const RuleSet rules = RuleSet::Build(paper, setup);
  NativePort port(mesh);
  RemovalBudget budget;
  KernelStats stats;
  const double cos_dev = std::cos(25.0 * std::numbers::pi / 180.0) - 1e-9;
  int removed = 0;
  for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v) {
    if (mesh.IsRemoved(v) || mesh.status()[v].load() != kRemovable) continue;
    Ring before;
    ASSERT_EQ(GatherRing(port, v, before), RingResult::kOk);
    RemovalKernel<NativePort> kernel(port, rules, /*quadric=*/true, budget, stats);
    if (kernel.TryRemove(v) != Outcome::kRemoved) continue;
    ++removed;
    const HalfEdgeQ* he = mesh.halfedges();
    const VertexQ* vx = mesh.vertices();
    for (int i = 0; i < before.faces; ++i) {
      const uint32_t f = FaceOf(before.out[i]);
      if (mesh.IsFaceRemoved(f)) continue;
      DVec3 p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = ToD(Vec3{vx[he[3 * f + k].target].x, vx[he[3 * f + k].target].y,
                        vx[he[3 * f + k].target].z});
      for (int k = 0; k < 3; ++k) {
        const DVec3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
        EXPECT_GE(std::acos(Dot(u, w) / (Norm(u) * Norm(w))) * 180.0 / std::numbers::pi,
                  10.0 - 1e-4)
            << "face " << f << " after removing " << v;
      }
      const DVec3 n_old =
          Cross(ToD(before.pos[i]) - ToD(before.center_pos),
                ToD(before.pos[(i + 1) % before.neighbours()]) - ToD(before.center_pos));
      const DVec3 n_new = Cross(p[1] - p[0], p[2] - p[0]);
      EXPECT_GE(Dot(n_old, n_new) / (Norm(n_old) * Norm(n_new)), cos_dev)
          << "face " << f << " after removing " << v;
      EXPECT_LE(mesh.face_attrs()[f].error, setup.tolerance) << "face " << f;
    }
  }
  EXPECT_GT(removed, 500);
  EXPECT_GT(stats.rejections[static_cast<int>(Reject::kTolerance)], 0u);
  EXPECT_GT(stats.rejections[static_cast<int>(Reject::kMinAngle)] +
                stats.rejections[static_cast<int>(Reject::kNormalDeviation)],
            0u);
  ASSERT_EQ(HalfEdgeInvariantViolation(mesh), "");
  ExpectSameTopology(raw, mesh);
}

// A commit changes the fans of the vertices it locked: with requeue_changed, those refused
// before are candidates again; others keep their state; without it (the paper's form) nothing
// changes until the next reconsideration.
TEST(Kernel, ACollapseMakesTheRefusedVerticesOfItsFanCandidatesAgain) {
  for (const bool requeue : {false, true}) {
    const RawMesh raw = testing::FlatGrid(6);
    Harness h(raw);
    const uint32_t center = 3 * 7 + 3, neighbour = 3 * 7 + 4, far = 6 * 7 + 6;
    h.mesh.status()[neighbour].store(kNotRemovable | kRetryBit);
    h.mesh.status()[far].store(kNotRemovable);
    ASSERT_EQ(h.Remove(center, requeue), Outcome::kRemoved);
    EXPECT_EQ(h.Status(neighbour), requeue ? kRemovable : (kNotRemovable | kRetryBit));
    EXPECT_EQ(h.Status(far), kNotRemovable);
  }
}

// A refusal that depends on V's fan alone (here the minimum angle) marks V plainly: it waits
// for its fan to change. One that read beyond it (a tetrahedron's valence: the opposite
// vertices' fans) also marks kRetryBit, so that reconsideration retries it; the paper's form
// never marks it.
TEST(Kernel, RefusalsBeyondTheFanAreMarkedForReconsideration) {
  SimplifyOptions sharp;
  sharp.min_angle_deg = 59;  // no collapse of a grid keeps every angle at 59 degrees
  sharp.strict_min_angle = true;
  sharp.feature_angle_deg = 180;
  Harness grid(testing::FlatGrid(4), sharp);
  const uint32_t center = 2 * 5 + 2;
  ASSERT_EQ(grid.Remove(center, /*requeue_changed=*/true), Outcome::kRejected);
  EXPECT_EQ(grid.Status(center), kNotRemovable);
  EXPECT_GT(grid.stats.rejections[static_cast<int>(Reject::kMinAngle)], 0u);

  SimplifyOptions topology;
  topology.topology_only = true;
  topology.feature_angle_deg = 180;
  for (const bool requeue : {false, true}) {
    Harness tet(testing::Tetrahedron(), topology);
    ASSERT_EQ(tet.Remove(0, requeue), Outcome::kRejected);
    EXPECT_EQ(tet.Status(0), requeue ? (kNotRemovable | kRetryBit) : kNotRemovable);
  }
}

}  // namespace
}  // namespace femsimp
