#include "engine/seams.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "engine/features.h"
#include "engine/io/mesh_io.h"
#include "engine/kernel.h"
#include "engine/mesh.h"
#include "engine/mesh_checks.h"
#include "engine/port.h"
#include "engine/prepare.h"
#include "engine/repair.h"
#include "engine/rule.h"
#include "engine/simplify.h"
#include "tests/judge/seam_conformity.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using Point = std::array<float, 3>;

// Builds soups from axis-aligned or slanted rectangles on a lattice: vertices at equal lattice
// points are shared, so rectangles that touch share edges (and make seams where three meet).
class Lattice {
 public:
  explicit Lattice(int n) : n_(n) {}

  // A rectangle origin + s * u + t * v, s and t in [0, 1], n x n quads, facing u x v (or its
  // opposite when flip).
  void AddRect(Point origin, Point u, Point v, bool flip = false, uint32_t group = 0) {
    auto id = [&](int i, int j) {
      Point p;
      for (int k = 0; k < 3; ++k)
        p[k] = origin[k] + (u[k] * float(i) + v[k] * float(j)) / float(n_);
      return Vertex(p);
    };
    for (int i = 0; i < n_; ++i)
      for (int j = 0; j < n_; ++j) {
        const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
        Face(a, b, c, flip, group);
        Face(a, c, d, flip, group);
      }
  }
  const RawMesh& mesh() const { return mesh_; }

 private:
  uint32_t Vertex(const Point& p) {
    // Coordinates are multiples of 1 / n (times small integers): round to the lattice.
    const std::array<long, 3> key = {std::lround(p[0] * 64.0f * float(n_)),
                                     std::lround(p[1] * 64.0f * float(n_)),
                                     std::lround(p[2] * 64.0f * float(n_))};
    auto [it, added] = ids_.try_emplace(key, uint32_t(mesh_.num_vertices()));
    if (added) mesh_.positions.insert(mesh_.positions.end(), p.begin(), p.end());
    return it->second;
  }
  void Face(uint32_t a, uint32_t b, uint32_t c, bool flip, uint32_t group) {
    if (flip) std::swap(b, c);
    mesh_.triangles.insert(mesh_.triangles.end(), {a, b, c});
    if (group != 0 || !mesh_.face_groups.empty()) {
      mesh_.face_groups.resize(mesh_.num_faces() - 1, 0);
      mesh_.face_groups.push_back(group);
    }
  }

  int n_;
  RawMesh mesh_;
  std::map<std::array<long, 3>, uint32_t> ids_;
};

// Outward faces of the box [x0, x1] x [0, 1] x [0, 1] (n quads per unit).
void AddBox(Lattice& l, float x0, float x1, float y0 = 0, float y1 = 1) {
  const float dx = x1 - x0, dy = y1 - y0;
  l.AddRect({x0, y0, 0}, {0, 0, 1}, {0, dy, 0});   // x = x0, facing -x
  l.AddRect({x1, y0, 0}, {0, dy, 0}, {0, 0, 1});   // x = x1, facing +x
  l.AddRect({x0, y0, 0}, {dx, 0, 0}, {0, 0, 1});   // y = y0, facing -y
  l.AddRect({x0, y1, 0}, {0, 0, 1}, {dx, 0, 0});   // y = y1, facing +y
  l.AddRect({x0, y0, 0}, {0, dy, 0}, {dx, 0, 0});  // z = 0, facing -z
  l.AddRect({x0, y0, 1}, {dx, 0, 0}, {0, dy, 0});  // z = 1, facing +z
}

// Two unit boxes sharing the face x = 1: the 2 x 1 x 1 box with an internal wall. The wall's
// triangles are listed once (as an assembly exporter writes a shared face), so its border edges
// have three faces.
RawMesh TwoBoxesSharingAFace(int n) {
  Lattice l(n);
  l.AddRect({0, 0, 0}, {0, 0, 1}, {0, 1, 0});  // x = 0
  l.AddRect({2, 0, 0}, {0, 1, 0}, {0, 0, 1});  // x = 2
  for (float x0 : {0.f, 1.f}) {  // the long faces, in two halves so that the wall border is shared
    l.AddRect({x0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    l.AddRect({x0, 1, 0}, {0, 0, 1}, {1, 0, 0});
    l.AddRect({x0, 0, 0}, {0, 1, 0}, {1, 0, 0});
    l.AddRect({x0, 0, 1}, {1, 0, 0}, {0, 1, 0});
  }
  l.AddRect({1, 0, 0}, {0, 1, 0}, {0, 0, 1});  // the wall
  return l.mesh();
}

// Two closed unit boxes touching along the edge x = 1, y = 1: four faces around it.
RawMesh TwoBoxesSharingAnEdge(int n) {
  Lattice l(n);
  AddBox(l, 0, 1, 0, 1);
  AddBox(l, 1, 2, 1, 2);
  return l.mesh();
}

// Three open pages on one spine (the z axis), at angles 0, 100 and 230 degrees.
RawMesh ThreePages(int n) {
  Lattice l(n);
  for (double deg : {0.0, 100.0, 230.0}) {
    const double a = deg * std::numbers::pi / 180.0;
    l.AddRect({0, 0, 0}, {0, 0, 1}, {float(std::cos(a)), float(std::sin(a)), 0});
  }
  return l.mesh();
}

// A shell assembly: an L-bracket (plates z = 0 and x = 0, bent along the y axis, one sheet) with
// a rib in the plane y = 0.5 welded to both legs. The rib's two welded edges are seams of three
// faces; they meet at the bend; the plates' outer edges are open boundaries. No T-junctions.
RawMesh RibbedBracket(int n) {
  Lattice l(n);
  for (float y0 : {0.f, 0.5f}) {
    l.AddRect({0, y0, 0}, {1, 0, 0}, {0, 0.5f, 0}, false, 1);  // leg z = 0
    l.AddRect({0, y0, 0}, {0, 0.5f, 0}, {0, 0, 1}, false, 2);  // leg x = 0
  }
  l.AddRect({0, 0.5f, 0}, {0, 0, 1}, {1, 0, 0}, false, 3);  // the rib
  return l.mesh();
}

Point PointOf(const RawMesh& m, uint32_t v) {
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

std::set<Point> SeamPoints(const RawMesh& m) {
  std::set<Point> out;
  for (const EdgeUse& e : NonManifoldEdges(m)) {
    out.insert(PointOf(m, e.a));
    out.insert(PointOf(m, e.b));
  }
  return out;
}

// Components of the sheets: faces connected across manifold edges only.
int64_t SheetCount(RawMesh m) {
  absl::StatusOr<SeamMap> map = SplitSeams(m);
  EXPECT_TRUE(map.ok()) << map.status();
  return TopologyOf(m).components;
}

struct SeamRun {
  RawMesh input, split, output;
  SeamMap map;
  RejoinReport report;
  SimplifyResult result;
};

// Split -> Build -> Simplify -> ToRaw -> Rejoin, checking every step.
SeamRun RunWithSeams(const RawMesh& input, const SimplifyOptions& options) {
  SeamRun run;
  run.input = input;
  run.split = input;
  absl::StatusOr<SeamMap> map = SplitSeams(run.split);
  EXPECT_TRUE(map.ok()) << map.status();
  if (!map.ok()) return run;
  run.map = *map;
  absl::StatusOr<Mesh> mesh = Mesh::Build(run.split);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  if (!mesh.ok()) return run;
  absl::StatusOr<SimplifyResult> result = Simplify(*mesh, options);
  EXPECT_TRUE(result.ok()) << result.status();
  if (!result.ok()) return run;
  run.result = *result;
  EXPECT_EQ(HalfEdgeInvariantViolation(*mesh), "");
  std::vector<uint32_t> ids;
  run.output = mesh->ToRaw(&ids);
  absl::StatusOr<RejoinReport> report = RejoinSeams(run.output, ids, run.map);
  EXPECT_TRUE(report.ok()) << report.status();
  if (report.ok()) run.report = *report;
  return run;
}

// What every assembly must keep: the seams conforming (every sheet meeting there with the same
// seam vertices, at input points, each seam the input's simplified along itself, junctions
// kept), the sheets and their topology, each sheet a valid mesh; and the output is smaller.
void ExpectSeamsConform(const SeamRun& run, bool reduces = true) {
  EXPECT_TRUE(run.report.conforming())
      << run.report.changed_seams.size() << " seams changed, " << run.report.new_seams.size()
      << " new, " << run.report.missing_seam_vertices << " seam vertices missing";
  // The judge's independent check, from the soups alone.
  const judge::SeamConformity judged = judge::CheckSeamConformity(run.input, run.output);
  EXPECT_TRUE(judged.problems.empty()) << judged.problems.front();
  EXPECT_GT(judged.input_seams, 0u);
  const std::set<Point> in_points = SeamPoints(run.input);
  // Seam vertices of the output: input seam vertices, each once, where it was.
  std::set<uint32_t> seam_inputs;
  for (uint32_t w : run.map.seam_vertices) seam_inputs.insert(run.map.original[w]);
  std::map<uint32_t, int> seen;
  std::set<Point> kept;
  for (uint32_t o = 0; o < run.output.num_vertices(); ++o) {
    const uint32_t v = run.report.input_vertex[o];
    if (!seam_inputs.count(v)) continue;
    ++seen[v];
    EXPECT_EQ(PointOf(run.output, o), PointOf(run.input, v));
    kept.insert(PointOf(run.input, v));
  }
  for (const auto& [v, n] : seen) EXPECT_EQ(n, 1) << "input vertex " << v;
  const std::set<Point> out_points = SeamPoints(run.output);
  for (const Point& p : out_points) EXPECT_TRUE(in_points.count(p)) << "seam point not an input's";
  std::set<Point> kept_on_seams;
  for (const Point& p : kept)
    if (in_points.count(p)) kept_on_seams.insert(p);
  EXPECT_EQ(out_points, kept_on_seams);
  const SoupTopology in = TopologyOf(run.input), out = TopologyOf(run.output);
  EXPECT_EQ(out.euler(), in.euler());
  EXPECT_EQ(out.components, in.components);
  EXPECT_EQ(out.boundary_edges > 0, in.boundary_edges > 0);
  EXPECT_EQ(SheetCount(run.output), SheetCount(run.input));
  RawMesh sheets = run.output;
  ASSERT_TRUE(SplitSeams(sheets).ok());
  absl::StatusOr<Mesh> rebuilt = Mesh::Build(sheets);
  EXPECT_TRUE(rebuilt.ok()) << rebuilt.status();
  if (reduces) {
    EXPECT_LT(run.output.num_vertices(), run.input.num_vertices());
  }
  EXPECT_EQ(run.output.num_faces(), run.result.output_faces);
}

// How many seam points the output keeps of the input's, and how many seam points the passes
// reported removing.
std::pair<size_t, size_t> SeamPointsKept(const SeamRun& run) {
  return {SeamPoints(run.output).size(), SeamPoints(run.input).size()};
}
uint64_t SeamPointsRemoved(const SimplifyResult& r) {
  uint64_t n = 0;
  for (const PassStats& p : r.passes) n += p.seam_points_removed;
  return n;
}

TEST(SplitSeams, TwoBoxesSharingAFaceMakeThreeSheets) {
  RawMesh m = TwoBoxesSharingAFace(4);
  const size_t nv = m.num_vertices(), nf = m.num_faces();
  EXPECT_FALSE(Mesh::Build(m).ok());  // the wall's border has edges of three faces
  const std::vector<uint32_t> tri_before = m.triangles;
  absl::StatusOr<SeamMap> map = SplitSeams(m);
  ASSERT_TRUE(map.ok()) << map.status();
  EXPECT_EQ(map->seams.size(), 16u);  // the wall's border: 4 sides of 4 edges
  for (const EdgeUse& e : map->seams) EXPECT_EQ(e.faces, 3u);
  EXPECT_EQ(map->split_vertices, 16u);  // its 16 border vertices, each in 3 sheets
  EXPECT_EQ(map->copies, 32u);
  EXPECT_EQ(map->seam_vertices.size(), 48u);
  EXPECT_EQ(m.locked_vertices, map->seam_vertices);
  EXPECT_EQ(m.num_vertices(), nv + 32);
  EXPECT_EQ(m.num_faces(), nf);
  for (size_t c = 0; c < m.triangles.size(); ++c)  // faces name copies of their own vertices
    EXPECT_EQ(map->original[m.triangles[c]], tri_before[c]);
  for (uint32_t w = 0; w < m.num_vertices(); ++w)
    EXPECT_EQ(PointOf(m, w), PointOf(m, map->original[w]));
  EXPECT_TRUE(NonManifoldEdges(m).empty());
  const SoupTopology t = TopologyOf(m);
  EXPECT_EQ(t.components, 3);           // two open boxes and the wall
  EXPECT_EQ(t.boundary_edges, 3 * 16);  // the seam, once in each sheet
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  for (uint32_t w = 0; w < m.num_vertices(); ++w)
    EXPECT_EQ(mesh->IsLocked(w),
              std::binary_search(map->seam_vertices.begin(), map->seam_vertices.end(), w));
}

TEST(SplitSeams, ManifoldMeshIsUntouched) {
  for (const RawMesh& input : {testing::MakeTorus(12, 8), testing::FlatGrid(5)}) {
    RawMesh m = input;
    absl::StatusOr<SeamMap> map = SplitSeams(m);
    ASSERT_TRUE(map.ok()) << map.status();
    EXPECT_TRUE(map->empty());
    EXPECT_TRUE(map->original.empty());
    EXPECT_EQ(m.positions, input.positions);
    EXPECT_EQ(m.triangles, input.triangles);
    EXPECT_TRUE(m.locked_vertices.empty());
  }
}

TEST(SplitSeams, RejectsIndicesOutOfRange) {
  RawMesh m = testing::SingleTriangle();
  m.triangles[1] = 7;
  EXPECT_FALSE(SplitSeams(m).ok());
}

TEST(SplitSeams, AgreesWithRepair) {
  for (const RawMesh& input :
       {TwoBoxesSharingAFace(3), TwoBoxesSharingAnEdge(3), ThreePages(3), RibbedBracket(4)}) {
    RawMesh repaired = input;
    absl::StatusOr<RepairResult> repair = RepairMesh(repaired, RepairOptions{});
    ASSERT_TRUE(repair.ok()) << repair.status();
    std::vector<std::pair<uint32_t, uint32_t>> from_repair, found;
    for (const SeamEdge& s : repair->seams) from_repair.push_back({s.a, s.b});
    for (const EdgeUse& e : NonManifoldEdges(repaired)) found.push_back({e.a, e.b});
    EXPECT_FALSE(found.empty());
    EXPECT_EQ(found, from_repair);
    RawMesh split = repaired;
    ASSERT_TRUE(SplitSeams(split).ok());
    EXPECT_TRUE(Mesh::Build(split).ok());
  }
}

TEST(SplitSeams, FourFacesAroundAnEdge) {
  RawMesh m = TwoBoxesSharingAnEdge(3);
  absl::StatusOr<SeamMap> map = SplitSeams(m);
  ASSERT_TRUE(map.ok()) << map.status();
  EXPECT_EQ(map->seams.size(), 3u);
  for (const EdgeUse& e : map->seams) EXPECT_EQ(e.faces, 4u);
  // Each box opens into a slit along the edge (its two faces there are in different fans at the
  // inner vertices of the edge): 3 edges on 2 sides of 2 boxes.
  const SoupTopology t = TopologyOf(m);
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.boundary_edges, 12);
  EXPECT_EQ(map->split_vertices, 4u);
  EXPECT_EQ(map->copies, 2u * 1 + 2u * 3);  // the ends in 2 fans, the inner vertices in 4
  EXPECT_TRUE(Mesh::Build(m).ok());
}

// A locked vertex is never removed nor moved, although its neighbours may collapse onto it.
TEST(LockedVertices, StayWhereTheyAre) {
  RawMesh m = testing::FlatGrid(12);  // 13 x 13
  std::set<Point> locked_points;
  for (uint32_t i = 0; i <= 12; ++i) {  // the middle row, and one more vertex
    m.locked_vertices.push_back(6 * 13 + i);
    locked_points.insert(PointOf(m, 6 * 13 + i));
  }
  m.locked_vertices.push_back(3 * 13 + 3);
  locked_points.insert(PointOf(m, 3 * 13 + 3));
  absl::StatusOr<Mesh> mesh = Mesh::Build(m);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  const FeatureSummary features = MarkFeatures(*mesh, 30.0);
  EXPECT_EQ(features.corner_vertices, 4u);  // the grid's corners; locked ones are not counted
  for (uint32_t v : m.locked_vertices) EXPECT_EQ(mesh->status()[v].load(), kFixed);
  SimplifyOptions options;
  options.ratio = 0.1;
  ASSERT_TRUE(Simplify(*mesh, options).ok());
  EXPECT_EQ(HalfEdgeInvariantViolation(*mesh), "");
  std::vector<uint32_t> ids;
  const RawMesh out = mesh->ToRaw(&ids);
  ASSERT_EQ(ids.size(), out.num_vertices());
  EXPECT_LT(out.num_vertices(), m.num_vertices() / 2);
  std::set<Point> out_locked;
  for (uint32_t o : out.locked_vertices) {
    out_locked.insert(PointOf(out, o));
    EXPECT_TRUE(mesh->IsLocked(ids[o]));
  }
  EXPECT_EQ(out_locked, locked_points);
  for (uint32_t o = 0; o < out.num_vertices(); ++o) EXPECT_EQ(PointOf(out, o), PointOf(m, ids[o]));
  // Locking a vertex does not pin its neighbours: some of the lone one's are gone.
  const uint32_t lone = 3 * 13 + 3;
  std::set<uint32_t> neighbours, kept(ids.begin(), ids.end());
  for (size_t f = 0; f < m.num_faces(); ++f)
    for (int i = 0; i < 3; ++i)
      if (m.triangles[3 * f + i] == lone)
        for (int j = 0; j < 3; ++j) neighbours.insert(m.triangles[3 * f + j]);
  neighbours.erase(lone);
  size_t removed = 0;
  for (uint32_t u : neighbours) removed += !kept.count(u);
  EXPECT_GT(removed, 0u);
}

TEST(LockedVertices, OutOfRangeIsRefused) {
  RawMesh m = testing::Tetrahedron();
  m.locked_vertices = {4};
  EXPECT_FALSE(Mesh::Build(m).ok());
}

SimplifyOptions Reduce(double ratio) {
  SimplifyOptions options;
  options.ratio = ratio;
  return options;
}

TEST(Seams, TwoBoxesSharingAFaceSimplifiedAndRejoined) {
  const SeamRun run = RunWithSeams(TwoBoxesSharingAFace(10), SimplifyOptions{});
  ExpectSeamsConform(run);
  // The wall's border is a square of 40 seam points, each in three sheets: its straight sides
  // are simplified along themselves down to (near) its four corners, every copy together.
  const auto [out, in] = SeamPointsKept(run);
  EXPECT_EQ(in, 40u);
  EXPECT_GE(out, 4u);
  EXPECT_LE(out, 12u);
  EXPECT_EQ(run.report.merged_vertices, 2u * out);
  EXPECT_EQ(SeamPointsRemoved(run.result), in - out);
}

TEST(Seams, FourFacesAroundAnEdge) {
  ExpectSeamsConform(RunWithSeams(TwoBoxesSharingAnEdge(8), Reduce(0.2)));
}

TEST(Seams, ThreePagesOnASpine) {
  const SeamRun run = RunWithSeams(ThreePages(10), SimplifyOptions{});
  ExpectSeamsConform(run);
  // A straight spine of 11 points: its two ends stay, the inner points may all go.
  const auto [out, in] = SeamPointsKept(run);
  EXPECT_EQ(in, 11u);
  EXPECT_LE(out, 4u);
  EXPECT_EQ(SeamPointsRemoved(run.result), in - out);
}

// A seam point removed in one sheet only (what the seam stage never does) breaks the seam: the
// rejoin says so, and so does the judge.
TEST(Seams, CopyRemovedAloneIsCaught) {
  RawMesh split = ThreePages(4);
  const RawMesh input = split;
  absl::StatusOr<SeamMap> map = SplitSeams(split);
  ASSERT_TRUE(map.ok()) << map.status();
  absl::StatusOr<Mesh> mesh = Mesh::Build(split);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  SimplifyOptions options;
  RuleSetup setup;
  setup.cos_feature = std::cos(options.feature_angle_deg * std::numbers::pi / 180.0);
  const RuleSet rules = RuleSet::Build(options, setup);
  MarkFeatures(*mesh, options.feature_angle_deg);
  // The copy of the spine point (0, 0, 0.5) in one sheet, onto the point (0, 0, 0.25) there.
  uint32_t copy = kNone, onto = kNone;
  for (uint32_t v = 0; v < mesh->vertex_capacity() && onto == kNone; ++v) {
    const VertexQ& q = mesh->vertices()[v];
    if (q.x != 0 || q.y != 0 || q.z != 0.5f) continue;
    copy = v;
    NativePort port(*mesh);
    Ring ring;
    ASSERT_EQ(GatherRing(port, v, ring), RingResult::kOk);
    for (int i = 0; i < ring.neighbours(); ++i)
      if (ring.pos[i].x == 0 && ring.pos[i].y == 0 && ring.pos[i].z == 0.25f) onto = ring.nbr[i];
  }
  ASSERT_NE(onto, kNone);
  NativePort port(*mesh);
  RemovalBudget budget;
  KernelStats stats;
  RemovalKernel<NativePort> kernel(port, rules, /*quadric=*/false, budget, stats);
  Reject refused = Reject::kCount;
  ASSERT_EQ(kernel.HoldCollapse(copy, onto, {}, &refused), Verdict::kPass) << RejectName(refused);
  kernel.CommitHeld();
  std::vector<uint32_t> ids;
  RawMesh out = mesh->ToRaw(&ids);
  absl::StatusOr<RejoinReport> report = RejoinSeams(out, ids, *map);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_FALSE(report->conforming());
  EXPECT_FALSE(report->changed_seams.empty() && report->new_seams.empty());
  EXPECT_FALSE(judge::CheckSeamConformity(input, out).problems.empty());
  // The job's error names the first edge that differs by where its ends are.
  const absl::StatusOr<RawMesh> joined = OutputMesh(*mesh, *map, {});
  EXPECT_EQ(joined.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(joined.status().message().find("the first: a "), std::string::npos) << joined.status();
  EXPECT_NE(joined.status().message().find("(0, 0, 0."), std::string::npos) << joined.status();
}

// The paper's preset has no tolerance: still, a seam point moves only with all its copies.
TEST(Seams, PaperPresetSimplifiesSeamsTogether) {
  SimplifyOptions options = PresetOptions(Preset::kPaper);
  options.ratio = 0.2;
  const SeamRun run = RunWithSeams(RibbedBracket(12), options);
  ExpectSeamsConform(run);
  EXPECT_GT(SeamPointsRemoved(run.result), 0u);
}

// The seam stage is sequential and in point order: the output does not depend on the thread or
// SPE count, or on the back end.
TEST(Seams, SameOutputForAnyContextCountAndBackEnd) {
  for (const RawMesh& input : {RibbedBracket(12), TwoBoxesSharingAnEdge(8)}) {
    SimplifyOptions one;
    one.tolerance_relative = 0.01;
    const SeamRun reference = RunWithSeams(input, one);
    ExpectSeamsConform(reference);
    EXPECT_GT(SeamPointsRemoved(reference.result), 0u);
    SimplifyOptions two = one;
    two.threads = 2;
    SimplifyOptions cell = one;
    cell.backend = Backend::kCell;
    cell.cell.spes = 4;
    for (const SimplifyOptions& other : {two, cell}) {
      const SeamRun run = RunWithSeams(input, other);
      EXPECT_EQ(run.output.positions, reference.output.positions);
      EXPECT_EQ(run.output.triangles, reference.output.triangles);
    }
  }
}

TEST(Seams, RibbedShellBracket) {
  const SeamRun run = RunWithSeams(RibbedBracket(12), Reduce(0.2));
  ExpectSeamsConform(run);
  // Groups survive the split and the rejoin.
  std::set<uint32_t> groups(run.output.face_groups.begin(), run.output.face_groups.end());
  EXPECT_EQ(groups, (std::set<uint32_t>{1, 2, 3}));
}

TEST(Seams, WithToleranceAndTwoThreads) {
  SimplifyOptions options;
  options.tolerance_relative = 0.005;
  options.threads = 2;
  ExpectSeamsConform(RunWithSeams(TwoBoxesSharingAFace(12), options));
  ExpectSeamsConform(RunWithSeams(RibbedBracket(12), options));
}

// The tolerance measured against the input: the compound seam collapses hand their fans'
// pieces on like any other (each copy's collapse commits its own).
TEST(Seams, WithTheToleranceMeasured) {
  SimplifyOptions options;
  options.tolerance_relative = 0.005;
  options.threads = 2;
  options.deviation_check = DeviationCheck::kMeasured;
  for (const RawMesh& mesh : {TwoBoxesSharingAFace(12), RibbedBracket(12)}) {
    const SeamRun run = RunWithSeams(mesh, options);
    ExpectSeamsConform(run);
    EXPECT_LE(run.result.deviation_bound, run.result.tolerance_abs);
  }
}

// fandisk 300,000 diagonals from the origin, where floats are 0.06 apart (4 % of the part):
// read as floats, its points weld into pinched vertices and non-manifold edges, the repair
// splits them into sheets with two copies of one point in a sheet, and a collapse could join a
// vertex to one copy while its neighbour was joined to the other. The job then failed at the
// rejoin ("the seams did not stay conforming", 1 new seam); the link condition compares points.
TEST(Seams, PartFarFromTheOriginKeepsItsSeams) {
  RawMesh far = testing::LoadTestMesh("fandisk.off");
  const double offset[3] = {3e5, 6e5, -9e4};
  for (size_t i = 0; i < far.positions.size(); ++i)
    far.positions[i] = static_cast<float>(double(far.positions[i]) + offset[i % 3]);
  SimplifyOptions tolerance;
  tolerance.tolerance_relative = 0.01;
  for (const SimplifyOptions& options : {SimplifyOptions{}, tolerance, Reduce(0.1)}) {
    absl::StatusOr<PreparedMesh> prepared = PrepareMesh(far, RepairOptions{});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    ASSERT_FALSE(prepared->seams.empty());
    absl::StatusOr<SimplifyResult> result = Simplify(prepared->mesh, options);
    ASSERT_TRUE(result.ok()) << result.status();
    EXPECT_LT(result->output_vertices, result->input_vertices / 2);
    absl::StatusOr<RawMesh> output =
        OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
    ASSERT_TRUE(output.ok()) << output.status();
    // The input the sheets were cut from: the repaired soup, as PrepareMesh made it.
    RawMesh repaired = far;
    ASSERT_TRUE(RepairMesh(repaired, RepairOptions{}).ok());
    const judge::SeamConformity judged = judge::CheckSeamConformity(repaired, *output);
    EXPECT_TRUE(judged.problems.empty()) << judged.problems.front();
  }
}

// The CAD-like assembly of scripts/make_cad_meshes.py (four boxes and a pin glued by gmsh's
// fragment), when it has been generated into the build tree.
TEST(Seams, CadAssembly) {
  for (const char* name : {"assembly_coarse.off", "assembly_fine.off", "assembly_occ_stl.stl"}) {
    const std::string path = std::string(FEMSIMP_CAD_MESHES) + "/" + name;
    if (!std::filesystem::exists(path))
      GTEST_SKIP() << path << " missing: run scripts/make_cad_meshes.py";
    absl::StatusOr<RawMesh> input = ReadMeshFile(path);
    ASSERT_TRUE(input.ok()) << input.status();
    ASSERT_TRUE(RepairMesh(*input, RepairOptions{}).ok());
    SimplifyOptions options;
    options.tolerance_relative = 0.005;
    const SeamRun run = RunWithSeams(*input, options);
    SimplifyOptions cell = Reduce(0.1);
    cell.backend = Backend::kCell;
    cell.cell.spes = 4;
    for (const SimplifyOptions& other : {Reduce(0.1), cell}) {
      const SeamRun reduced = RunWithSeams(*input, other);
      ExpectSeamsConform(reduced, name != std::string("assembly_occ_stl.stl"));
      std::printf("%s, ratio 0.1 (%s): V -> %zu\n", name,
                  other.backend == Backend::kCell ? "cell, 4 SPEs" : "native",
                  reduced.output.num_vertices());
    }
    // OpenCASCADE's own tessellation has only seam vertices and CAD corners: nothing to remove.
    ExpectSeamsConform(run, /*reduces=*/name != std::string("assembly_occ_stl.stl"));
    // The faces along the seams are simplified too: the self-intersection rule sees the other
    // sheets' seam copies as the same corners (RawMesh::point_ids), so they touch there by
    // design. Without that the fine assembly kept 14 % of its vertices.
    // The seams themselves are simplified along their curves (engine/seam_collapse.h): the
    // fine assembly kept 643 of 10,825 vertices with every seam point locked.
    const auto [out, in] = SeamPointsKept(run);
    if (name == std::string("assembly_fine.off")) {
      EXPECT_LT(run.output.num_vertices() * 20, run.input.num_vertices());
      EXPECT_LT(out * 2, in);
    }
    std::printf("%s: seam points %zu -> %zu\n", name, in, out);
    std::printf("%s: V %zu -> %zu, F %zu -> %zu, %zu seam edges, %zu seam vertices, %zu copies\n",
                name, run.input.num_vertices(), run.output.num_vertices(), run.input.num_faces(),
                run.output.num_faces(), run.map.seams.size(), run.map.split_vertices,
                run.map.copies);
  }
}

}  // namespace
}  // namespace femsimp
