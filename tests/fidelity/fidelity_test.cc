// Issue #5's fidelity guarantees, checked on the test meshes by the independent judge
// (tests/judge): the engine's output is measured from its triangle soup alone, and the engine's
// own reported figures are only compared against those measurements.
//
// Every distance the judge reports is a certified lower bound (docs in judge.h), so "measured
// <= bound" never fails an output that keeps the bound; the only slack added is the float
// storage of coordinates (judge::FloatStorageSlack), which no float output can beat.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "engine/simplify.h"
#include "tests/judge/inertia.h"
#include "tests/judge/judge.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

using judge::Vec3;

enum class Groups { kNone, kByNormal, kByPlane };

struct Case {
  std::string mesh;
  double tolerance_relative = 0.0;
  CostKind cost = CostKind::kQuadric;
  Backend backend = Backend::kNative;
  Groups groups = Groups::kNone;
  bool fields = false;
  double max_volume_change = 0.0;
  double max_centroid_shift = 0.0;
  double max_inertia_change = 0.0;
  Placement placement = Placement::kEndpoint;
  DeviationCheck deviation_check = DeviationCheck::kMapped;
};

std::string CaseName(const Case& c) {
  std::string name = c.mesh.substr(0, c.mesh.find('.'));
  name += c.tolerance_relative == 0.001 ? "_tol0p1pct" : "_tol1pct";
  name += c.cost == CostKind::kQuadric     ? "_quadric"
          : c.cost == CostKind::kDeviation ? "_deviation"
                                           : "_gaussian";
  if (c.backend == Backend::kCell) name += "_cell";
  if (c.groups == Groups::kByNormal) name += "_groupsByNormal";
  if (c.groups == Groups::kByPlane) name += "_groupsByPlane";
  if (c.fields) name += "_fields";
  if (c.max_volume_change > 0) name += "_volume";
  if (c.max_centroid_shift > 0) name += "_centroid";
  if (c.max_inertia_change > 0) name += "_inertia";
  if (c.placement == Placement::kOptimal) name += "_placed";
  if (c.deviation_check == DeviationCheck::kMeasured) name += "_measured";
  return name;
}
std::string ParamName(const ::testing::TestParamInfo<Case>& info) { return CaseName(info.param); }
void PrintTo(const Case& c, std::ostream* os) { *os << CaseName(c); }

Vec3 FaceCentroid(const RawMesh& m, size_t f) {
  Vec3 c{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) c[k] += m.positions[3 * m.triangles[3 * f + i] + k] / 3.0;
  return c;
}

std::pair<Vec3, Vec3> Bounds(const RawMesh& m) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (size_t i = 0; i < m.positions.size(); ++i) {
    lo[i % 3] = std::min<double>(lo[i % 3], m.positions[i]);
    hi[i % 3] = std::max<double>(hi[i % 3], m.positions[i]);
  }
  return {lo, hi};
}

// Face groups with ids that are neither 0-based nor contiguous, so renumbering would show:
// by the dominant axis of the face normal (up to six groups with jagged borders along curved
// parts), or by the plane through the middle of the bounding box normal to its longest side.
void AddGroups(RawMesh& m, Groups groups) {
  if (groups == Groups::kNone) return;
  const auto [lo, hi] = Bounds(m);
  int longest = 0;
  for (int k = 1; k < 3; ++k)
    if (hi[k] - lo[k] > hi[longest] - lo[longest]) longest = k;
  const double middle = (lo[longest] + hi[longest]) / 2;
  m.face_groups.resize(m.num_faces());
  for (size_t f = 0; f < m.num_faces(); ++f) {
    if (groups == Groups::kByPlane) {
      m.face_groups[f] = FaceCentroid(m, f)[longest] < middle ? 10 : 20;
      continue;
    }
    const uint32_t* t = &m.triangles[3 * f];
    Vec3 p[3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) p[i][k] = m.positions[3 * t[i] + k];
    const Vec3 u{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const Vec3 w{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
    m.face_groups[f] = 100 + 2 * axis + (n[axis] > 0);
  }
}

// A pressure growing with height (p = 1 + normalised z, one sign) and a load that changes sign
// along x, so that a group's net resultant is much smaller than its absolute load.
void AddFields(RawMesh& m) {
  const auto [lo, hi] = Bounds(m);
  FaceField pressure{"pressure", {}}, wave{"wave", {}};
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const Vec3 c = FaceCentroid(m, f);
    pressure.values.push_back(static_cast<float>(1.0 + (c[2] - lo[2]) / (hi[2] - lo[2])));
    wave.values.push_back(
        static_cast<float>(std::cos(2 * M_PI * (c[0] - lo[0]) / (hi[0] - lo[0]))));
  }
  m.face_fields = {pressure, wave};
}

struct Outcome {
  RawMesh input, output;
  SimplifyResult result;
  SimplifyOptions options;
  double diag = 0.0, tol = 0.0, slack = 0.0;
};

Outcome Simplified(const Case& c) {
  Outcome o;
  o.input = testing::LoadTestMesh(c.mesh);
  AddGroups(o.input, c.groups);
  if (c.fields) AddFields(o.input);
  o.diag = judge::BoundingBoxDiagonal(o.input);
  o.tol = c.tolerance_relative * o.diag;
  o.slack = judge::FloatStorageSlack(o.input);
  o.options.threads = 2;
  o.options.tolerance_relative = c.tolerance_relative;
  o.options.cost = c.cost;
  o.options.backend = c.backend;
  o.options.cell.spes = 3;
  o.options.max_volume_change = c.max_volume_change;
  o.options.max_centroid_shift = c.max_centroid_shift;
  o.options.max_inertia_change = c.max_inertia_change;
  o.options.max_field_change = 0.01;
  o.options.placement = c.placement;
  o.options.deviation_check = c.deviation_check;
  // Every blade triangle has an angle below 10 degrees, so the default minimum angle would
  // forbid every collapse there and leave the tolerance untested.
  if (c.mesh == "blade.off") o.options.min_angle_deg = 1.0;
  absl::StatusOr<Mesh> mesh = Mesh::Build(o.input);
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  if (!mesh.ok()) return o;
  absl::StatusOr<SimplifyResult> result = Simplify(*mesh, o.options);
  EXPECT_TRUE(result.ok()) << result.status();
  if (!result.ok()) return o;
  o.result = *result;
  o.output = mesh->ToRaw();
  std::printf("%s: %zu -> %zu vertices in %.3f s; tolerance %.3g (%.2g %% of the diagonal)\n",
              c.mesh.c_str(), o.input.num_vertices(), o.output.num_vertices(),
              o.result.engine_seconds, o.tol, 100 * c.tolerance_relative);
  return o;
}

// Hausdorff distance within the tolerance, and the engine's claimed bound honest; no
// self-intersection; the surface's topology unchanged.
void ExpectSurfaceFidelity(const Outcome& o) {
  ASSERT_GT(o.output.num_faces(), 0u);
  EXPECT_LT(o.output.num_vertices(), o.input.num_vertices()) << "nothing was simplified";
  const judge::Hausdorff h =
      judge::HausdorffDistance(o.input, o.output, judge::HausdorffErrorFor(o.tol));
  std::printf(
      "  Hausdorff in->out %.4g, out->in %.4g (%.3g %% / %.3g %% of the tolerance), "
      "engine bound %.4g, judged in %.2f s\n",
      h.a_to_b, h.b_to_a, 100 * h.a_to_b / o.tol, 100 * h.b_to_a / o.tol, o.result.deviation_bound,
      h.seconds);
  EXPECT_LE(h.a_to_b, o.tol + o.slack) << "input point farther than the tolerance from output";
  EXPECT_LE(h.b_to_a, o.tol + o.slack) << "output point farther than the tolerance from input";
  EXPECT_NEAR(o.result.tolerance_abs, o.tol, 1e-5 * o.tol) << "engine applied another tolerance";
  EXPECT_LE(o.result.deviation_bound, o.result.tolerance_abs);
  // A certified lower bound above the engine's "guaranteed" bound proves the bound wrong.
  EXPECT_LE(h.two_sided(), o.result.deviation_bound + o.slack) << "engine bound is not a bound";

  EXPECT_FALSE(judge::SelfIntersects(o.output));
  const judge::Topology in = judge::ComputeTopology(o.input),
                        out = judge::ComputeTopology(o.output);
  EXPECT_TRUE(out.manifold()) << out.nonmanifold_edges << " non-manifold edges, "
                              << out.nonmanifold_vertices << " non-manifold vertices, "
                              << out.misoriented_edges << " misoriented edges";
  EXPECT_EQ(in.closed_manifold(), out.closed_manifold());
  EXPECT_EQ(in.genus(), out.genus());
  EXPECT_EQ(in.components, out.components);
  EXPECT_EQ(in.boundary_loops, out.boundary_loops);
}

// Points along every input feature edge are within the tolerance of the output's feature
// edges, found from the geometry: the input at the feature angle, the output at half of it (a
// soft crease just above the angle stays in place but may come out softer).
void ExpectFeaturesKept(const Outcome& o, double angle_deg) {
  const judge::FeatureCoverage c =
      judge::CheckFeatureCoverage(o.input, o.output, angle_deg, 0.1 * o.tol, angle_deg / 2);
  std::printf(
      "  features at %.0f deg: %zu input edges, %zu output edges; farthest input feature "
      "point %.4g from output lines (%.3g %% of the tolerance); reverse %.4g\n",
      angle_deg, c.original_edges, c.simplified_edges, c.max_distance, 100 * c.max_distance / o.tol,
      c.reverse_max_distance);
  EXPECT_GT(c.original_edges, 0u);
  EXPECT_LE(c.max_distance, o.tol + o.slack)
      << "feature point (" << c.worst_point[0] << ", " << c.worst_point[1] << ", "
      << c.worst_point[2] << ") lost";
}

void ExpectGroupsAndFields(const Outcome& o) {
  if (!o.input.face_groups.empty()) {
    ASSERT_EQ(o.output.face_groups.size(), o.output.num_faces());
  }
  const std::vector<uint32_t> in = judge::GroupIds(o.input), out = judge::GroupIds(o.output);
  EXPECT_EQ(in, out) << "groups were made up or lost";
  if (!o.input.face_groups.empty()) {
    // Each group stays where it was: a face that straddled a border or wandered into another
    // group's region would put its group farther than the tolerance from where it was.
    for (const auto& [group, h] :
         judge::GroupHausdorffDistances(o.input, o.output, judge::HausdorffErrorFor(o.tol)))
      EXPECT_LE(h.two_sided(), o.tol + o.slack) << "group " << group;
    // Borders alone (180 degrees: only boundaries and group borders are features).
    ExpectFeaturesKept(o, 180.0);
  }

  ASSERT_EQ(o.output.face_fields.size(), o.input.face_fields.size());
  double worst = 0.0;
  for (size_t i = 0; i < o.input.face_fields.size(); ++i) {
    EXPECT_EQ(o.output.face_fields[i].name, o.input.face_fields[i].name);
    ASSERT_EQ(o.output.face_fields[i].values.size(), o.output.num_faces());
    const auto before = judge::FieldResultants(o.input, i);
    const auto after = judge::FieldResultants(o.output, i);
    for (const auto& [group, change] : judge::RelativeResultantChange(before, after)) {
      // Float storage: every area moves by up to perimeter * slack, every value is a float.
      const double slack = 1e-5;
      EXPECT_LE(change, o.options.max_field_change + slack)
          << "field " << o.input.face_fields[i].name << ", group " << group;
      worst = std::max(worst, change);
    }
  }
  std::printf("  worst resultant change %.4g (engine reports %.4g)\n", worst,
              o.result.max_field_change);
  EXPECT_NEAR(o.result.max_field_change, worst, 1e-4) << "engine misreports the field change";
}

void ExpectBudgets(const Outcome& o) {
  const judge::Topology topology = judge::ComputeTopology(o.input);
  const double area = judge::SurfaceProperties(o.input).area;
  Vec3 before, after;
  if (topology.closed_manifold()) {
    const judge::Solid a = judge::SolidProperties(o.input), b = judge::SolidProperties(o.output);
    const double change = (b.volume - a.volume) / a.volume;
    // Moving every vertex by the float slack sweeps at most area * slack of volume.
    const double volume_slack = area * o.slack / std::abs(a.volume);
    std::printf("  volume change %.4g %% (engine reports %.4g %%)\n", 100 * change,
                100 * o.result.volume_change);
    if (o.options.max_volume_change > 0) {
      EXPECT_LE(std::abs(change), o.options.max_volume_change + volume_slack);
    }
    EXPECT_NEAR(o.result.volume_change, change, 1e-5) << "engine misreports the volume change";
    before = a.centroid;
    after = b.centroid;
  } else {
    // An open surface encloses nothing: its centre of mass is that of the shell.
    before = judge::SurfaceProperties(o.input).centroid;
    after = judge::SurfaceProperties(o.output).centroid;
  }
  const double shift = std::hypot(after[0] - before[0], after[1] - before[1], after[2] - before[2]);
  std::printf("  centroid shift %.4g of the diagonal (engine reports %.4g)\n", shift / o.diag,
              o.result.centroid_shift);
  if (o.options.max_centroid_shift > 0) {
    EXPECT_LE(shift / o.diag, o.options.max_centroid_shift + 1e-6);
  }
  EXPECT_NEAR(o.result.centroid_shift, shift / o.diag, 1e-6)
      << "engine misreports the centroid shift";

  // Principal moments of inertia, by the judge's own integration.
  const auto inertia = topology.closed_manifold() ? judge::SolidInertia : judge::ShellInertia;
  const judge::InertiaFigures in = inertia(o.input), out = inertia(o.output);
  const double moment_change = judge::WorstPrincipalMomentChange(in, out);
  std::printf(
      "  principal moments %.6g %.6g %.6g -> %.6g %.6g %.6g: worst change %.4g %% "
      "(engine reports %.4g %%)\n",
      in.principal_moments[0], in.principal_moments[1], in.principal_moments[2],
      out.principal_moments[0], out.principal_moments[1], out.principal_moments[2],
      100 * moment_change, 100 * o.result.inertia_change);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(o.result.input_mass.principal_moments[k], in.principal_moments[k],
                1e-6 * std::abs(in.principal_moments[k]))
        << "engine misreports the input's moments";
  // Float storage moves every vertex by up to the slack: a relative change of a few slack /
  // size at most.
  const double moment_slack = 1e-5;
  if (o.options.max_inertia_change > 0) {
    EXPECT_LE(moment_change, o.options.max_inertia_change + moment_slack);
  }
  EXPECT_NEAR(o.result.inertia_change, moment_change, moment_slack)
      << "engine misreports the inertia change";
}

const std::vector<std::string> kMeshes = {"fandisk.off", "blade.off", "femur.off",
                                          "rotor_small.off"};

// ---- the surface at both tolerances, both costs ----------------------------------------------

class SurfaceFidelity : public ::testing::TestWithParam<Case> {};

TEST_P(SurfaceFidelity, WithinToleranceNoIntersectionSameTopology) {
  const Outcome o = Simplified(GetParam());
  ExpectSurfaceFidelity(o);
}

std::vector<Case> SurfaceCases() {
  std::vector<Case> cases;
  for (const std::string& mesh : kMeshes)
    for (double tol : {0.001, 0.01})
      for (CostKind cost : {CostKind::kQuadric, CostKind::kGaussianCurvature, CostKind::kDeviation})
        if (cost != CostKind::kDeviation || mesh != "blade.off")  // the blade is slow to judge
          cases.push_back({.mesh = mesh, .tolerance_relative = tol, .cost = cost});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Meshes, SurfaceFidelity, ::testing::ValuesIn(SurfaceCases()), ParamName);

// ---- fandisk's feature lines -------------------------------------------------------------------

class FeatureLines : public ::testing::TestWithParam<Case> {};

TEST_P(FeatureLines, EveryInputFeatureEdgeRepresented) {
  const Outcome o = Simplified(GetParam());
  ASSERT_GT(o.output.num_faces(), 0u);
  ExpectFeaturesKept(o, o.options.feature_angle_deg);
}

std::vector<Case> FeatureCases() {
  std::vector<Case> cases;
  for (double tol : {0.001, 0.01})
    for (CostKind cost : {CostKind::kQuadric, CostKind::kGaussianCurvature})
      cases.push_back({.mesh = "fandisk.off", .tolerance_relative = tol, .cost = cost});
  cases.push_back({.mesh = "fandisk.off", .tolerance_relative = 0.001, .backend = Backend::kCell});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Fandisk, FeatureLines, ::testing::ValuesIn(FeatureCases()), ParamName);

// ---- volume and centroid budgets ---------------------------------------------------------------

class Budgets : public ::testing::TestWithParam<Case> {};

TEST_P(Budgets, VolumeAndCentroidWithinBounds) {
  const Outcome o = Simplified(GetParam());
  ASSERT_GT(o.output.num_faces(), 0u);
  ExpectBudgets(o);
  ExpectSurfaceFidelity(o);
}

std::vector<Case> BudgetCases() {
  std::vector<Case> cases;
  // The blade is open: it encloses no volume, so only its (area) centroid has a budget; the
  // engine refuses a volume budget on it (tests/engine/fidelity_engine_test.cc).
  for (const std::string& mesh : kMeshes)
    cases.push_back({.mesh = mesh,
                     .tolerance_relative = 0.01,
                     .max_volume_change = mesh == "blade.off" ? 0.0 : 0.001,
                     .max_centroid_shift = 0.0005});
  cases.push_back({.mesh = "femur.off",
                   .tolerance_relative = 0.01,
                   .cost = CostKind::kGaussianCurvature,
                   .max_volume_change = 0.001,
                   .max_centroid_shift = 0.0005});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Meshes, Budgets, ::testing::ValuesIn(BudgetCases()), ParamName);

// The mass budgets an FE analyst states (issue 13): volume 0.1 %, principal moments 0.5 %, at a
// 1 % tolerance, on the closed meshes (an open surface's moments: tests/engine/inertia_test.cc).
std::vector<Case> InertiaCases() {
  std::vector<Case> cases;
  for (const std::string& mesh : kMeshes)
    if (mesh != "blade.off")
      cases.push_back({.mesh = mesh,
                       .tolerance_relative = 0.01,
                       .max_volume_change = 0.001,
                       .max_inertia_change = 0.005});
  cases.push_back({.mesh = "rotor_small.off",
                   .tolerance_relative = 0.01,
                   .backend = Backend::kCell,
                   .max_volume_change = 0.001,
                   .max_inertia_change = 0.005});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Inertia, Budgets, ::testing::ValuesIn(InertiaCases()), ParamName);

// ---- face groups and face fields ---------------------------------------------------------------

class GroupsAndFields : public ::testing::TestWithParam<Case> {};

TEST_P(GroupsAndFields, GroupsKeptResultantsWithinBudget) {
  const Outcome o = Simplified(GetParam());
  ASSERT_GT(o.output.num_faces(), 0u);
  ExpectGroupsAndFields(o);
  ExpectSurfaceFidelity(o);
}

std::vector<Case> GroupCases() {
  const Groups by_normal = Groups::kByNormal, by_plane = Groups::kByPlane;
  return {
      {.mesh = "fandisk.off", .tolerance_relative = 0.01, .groups = by_normal, .fields = true},
      {.mesh = "blade.off", .tolerance_relative = 0.01, .groups = by_plane, .fields = true},
      {.mesh = "femur.off", .tolerance_relative = 0.01, .groups = by_plane, .fields = true},
      {.mesh = "rotor_small.off", .tolerance_relative = 0.001, .groups = by_normal, .fields = true},
      // Fields without groups: one resultant over the whole surface.
      {.mesh = "femur.off",
       .tolerance_relative = 0.001,
       .cost = CostKind::kGaussianCurvature,
       .fields = true},
      {.mesh = "femur.off",
       .tolerance_relative = 0.01,
       .backend = Backend::kCell,
       .groups = by_plane,
       .fields = true},
  };
}
INSTANTIATE_TEST_SUITE_P(Meshes, GroupsAndFields, ::testing::ValuesIn(GroupCases()), ParamName);

// ---- the cell back end -------------------------------------------------------------------------

class CellBackend : public ::testing::TestWithParam<Case> {};

TEST_P(CellBackend, SameGuaranteesAsNative) {
  const Outcome o = Simplified(GetParam());
  ExpectSurfaceFidelity(o);
}

INSTANTIATE_TEST_SUITE_P(Meshes, CellBackend,
                         ::testing::Values(Case{.mesh = "fandisk.off",
                                                .tolerance_relative = 0.001,
                                                .backend = Backend::kCell},
                                           Case{.mesh = "rotor_small.off",
                                                .tolerance_relative = 0.01,
                                                .cost = CostKind::kGaussianCurvature,
                                                .backend = Backend::kCell}),
                         ParamName);

// ---- full-edge collapses with placement (option placement = optimal) ----------------------------

// The same guarantees with vertices placed off their input positions, on both back ends; the
// mass budgets keep the volume and the moments; the feature lines stay.
std::vector<Case> PlacementCases() {
  const Placement placed = Placement::kOptimal;
  std::vector<Case> cases;
  for (const char* mesh : {"fandisk.off", "femur.off", "rotor_small.off"})
    for (double tol : {0.001, 0.01})
      cases.push_back({.mesh = mesh,
                       .tolerance_relative = tol,
                       .cost = CostKind::kDeviation,
                       .placement = placed});
  cases.push_back({.mesh = "fandisk.off",
                   .tolerance_relative = 0.001,
                   .cost = CostKind::kDeviation,
                   .backend = Backend::kCell,
                   .placement = placed});
  cases.push_back({.mesh = "rotor_small.off",
                   .tolerance_relative = 0.01,
                   .cost = CostKind::kQuadric,
                   .backend = Backend::kCell,
                   .placement = placed});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Placement, SurfaceFidelity, ::testing::ValuesIn(PlacementCases()),
                         ParamName);

std::vector<Case> PlacementFeatureCases() {
  return {{.mesh = "fandisk.off",
           .tolerance_relative = 0.01,
           .cost = CostKind::kDeviation,
           .placement = Placement::kOptimal}};
}
INSTANTIATE_TEST_SUITE_P(Placement, FeatureLines, ::testing::ValuesIn(PlacementFeatureCases()),
                         ParamName);

std::vector<Case> PlacementBudgetCases() {
  std::vector<Case> cases;
  for (const char* mesh : {"fandisk.off", "femur.off", "rotor_small.off"})
    cases.push_back({.mesh = mesh,
                     .tolerance_relative = 0.01,
                     .cost = CostKind::kDeviation,
                     .max_volume_change = 0.001,
                     .max_inertia_change = 0.005,
                     .placement = Placement::kOptimal});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Placement, Budgets, ::testing::ValuesIn(PlacementBudgetCases()),
                         ParamName);

// ---- the tolerance measured against the input (option deviation_check = measured) -----------

// Two-sided within the tolerance by the judge, with the engine's reported bound honest, at both
// tolerances, in the deviation order and the quadric one; fandisk's feature lines stay.
std::vector<Case> MeasuredCases() {
  std::vector<Case> cases;
  for (const char* mesh : {"fandisk.off", "femur.off", "rotor_small.off"})
    for (double tol : {0.001, 0.01})
      cases.push_back({.mesh = mesh,
                       .tolerance_relative = tol,
                       .cost = CostKind::kDeviation,
                       .deviation_check = DeviationCheck::kMeasured});
  cases.push_back({.mesh = "rotor_small.off",
                   .tolerance_relative = 0.01,
                   .cost = CostKind::kQuadric,
                   .deviation_check = DeviationCheck::kMeasured});
  // Vertices placed where the tolerance refused the half-edge collapse.
  for (const char* mesh : {"fandisk.off", "rotor_small.off"})
    cases.push_back({.mesh = mesh,
                     .tolerance_relative = 0.01,
                     .cost = CostKind::kDeviation,
                     .placement = Placement::kOptimal,
                     .deviation_check = DeviationCheck::kMeasured});
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Measured, SurfaceFidelity, ::testing::ValuesIn(MeasuredCases()),
                         ParamName);

// ---- vertices placed on feature lines (either check, placement, budgets) ----------------------

// V and Vd on one feature line may merge at a point off it (the mass budgets' volume-keeping
// point on a curved crease), with the tolerance measured or the mapped bound, on both back ends:
// the judge finds the input's lines within the tolerance of the output's, each face group where
// it was, the budgets kept.
class LinePlacement : public ::testing::TestWithParam<Case> {};

TEST_P(LinePlacement, LinesGroupsAndBudgetsKept) {
  const Outcome o = Simplified(GetParam());
  ASSERT_GT(o.output.num_faces(), 0u);
  uint64_t on_lines = 0;
  for (const PassStats& p : o.result.passes) on_lines += p.placed_on_lines;
  std::printf("  %llu full-edge collapses on feature lines\n",
              static_cast<unsigned long long>(on_lines));
  EXPECT_GT(on_lines, 0u) << "no vertex was placed on a feature line";
  ExpectSurfaceFidelity(o);
  ExpectBudgets(o);
  ExpectFeaturesKept(o, o.options.feature_angle_deg);
  ExpectGroupsAndFields(o);
}

// Either check, on fandisk and rotor_small with and without two face groups; the mapped bound
// also on the cell back end (the measured check runs natively only).
std::vector<Case> LinePlacementCases(DeviationCheck check) {
  std::vector<Case> cases;
  for (const char* mesh : {"fandisk.off", "rotor_small.off"})
    for (Groups groups : {Groups::kNone, Groups::kByPlane})
      cases.push_back({.mesh = mesh,
                       .tolerance_relative = 0.01,
                       .cost = CostKind::kDeviation,
                       .groups = groups,
                       .max_volume_change = 0.001,
                       .max_inertia_change = 0.005,
                       .placement = Placement::kOptimal,
                       .deviation_check = check});
  if (check == DeviationCheck::kMapped) {
    Case cell = cases.back();
    cell.groups = Groups::kNone;
    cell.backend = Backend::kCell;
    cases.push_back(cell);
  }
  return cases;
}
INSTANTIATE_TEST_SUITE_P(Measured, LinePlacement,
                         ::testing::ValuesIn(LinePlacementCases(DeviationCheck::kMeasured)),
                         ParamName);
INSTANTIATE_TEST_SUITE_P(Mapped, LinePlacement,
                         ::testing::ValuesIn(LinePlacementCases(DeviationCheck::kMapped)),
                         ParamName);

std::vector<Case> MeasuredFeatureCases() {
  return {{.mesh = "fandisk.off",
           .tolerance_relative = 0.01,
           .cost = CostKind::kDeviation,
           .deviation_check = DeviationCheck::kMeasured}};
}
INSTANTIATE_TEST_SUITE_P(Measured, FeatureLines, ::testing::ValuesIn(MeasuredFeatureCases()),
                         ParamName);

}  // namespace
}  // namespace femsimp
