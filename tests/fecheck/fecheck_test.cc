// The FE check (fecheck/): mass properties, the eigenvalue table, the rigid-mode split and the
// child processes on their own; then tetgen + CalculiX end to end on a free-free beam, whose
// bending frequencies have a closed form (docs/FIDELITY.md, "FE check"), a box with a cavity,
// and the ways a check
// must fail: an open surface, a self-intersecting one, a missing tool, a cancel.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "engine/crossings.h"
#include "fecheck/calculix.h"
#include "fecheck/child_process.h"
#include "fecheck/fe_check.h"
#include "fecheck/solid_properties.h"
#include "fecheck/temp_dir.h"
#include "tests/support/fe_check.h"
#include "tests/support/files.h"
#include "tests/support/meshes.h"

namespace femsimp::fecheck {
namespace {

namespace fs = std::filesystem;

// A box [0,a] x [0,b] x [0,c] as six tetrahedra around its main diagonal.
TetMesh BoxTets(double a, double b, double c) {
  TetMesh m;
  for (int i = 0; i < 8; ++i)
    m.nodes.insert(m.nodes.end(), {a * (i & 1), b * (i >> 1 & 1), c * (i >> 2 & 1)});
  // Paths 0 -> 7 through the cube's corners, one tetrahedron each.
  const uint32_t paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (const auto& p : paths) m.tets.insert(m.tets.end(), {0, p[0], p[1], 7});
  // Tetrahedralise orients them; here the same rule, by hand.
  for (size_t t = 0; t < m.num_tets(); ++t) {
    uint32_t* v = &m.tets[4 * t];
    double e[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e[i][k] = m.nodes[3 * v[i + 1] + k] - m.nodes[3 * v[0] + k];
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (det < 0) std::swap(v[1], v[2]);
  }
  m.components = 1;
  return m;
}

TEST(SolidProperties, BoxOfSixTetrahedra) {
  const double a = 2, b = 1, c = 0.5, rho = 3;
  TetMesh m = BoxTets(a, b, c);
  for (size_t i = 0; i < m.nodes.size(); i += 3) m.nodes[i] += 100;  // far from the origin
  const SolidProperties p = MeasureSolid(m, rho);
  const double mass = rho * a * b * c;
  EXPECT_NEAR(p.volume, a * b * c, 1e-12);
  EXPECT_NEAR(p.centroid[0], 100 + a / 2, 1e-12);
  EXPECT_NEAR(p.centroid[1], b / 2, 1e-12);
  EXPECT_NEAR(p.centroid[2], c / 2, 1e-12);
  // Ascending: about x (b^2 + c^2), about y (a^2 + c^2), about z (a^2 + b^2), each m/12.
  EXPECT_NEAR(p.principal_moments[0], mass * (b * b + c * c) / 12, 1e-10);
  EXPECT_NEAR(p.principal_moments[1], mass * (a * a + c * c) / 12, 1e-10);
  EXPECT_NEAR(p.principal_moments[2], mass * (a * a + b * b) / 12, 1e-10);
  EXPECT_NEAR(p.diagonal, std::sqrt(a * a + b * b + c * c), 1e-12);
}

// The table as CalculiX 2.20 writes it (a free-free beam: six rigid-body modes, two of them
// with small negative eigenvalues, then six bending modes).
constexpr char kDat[] = R"(
     E I G E N V A L U E   O U T P U T

 MODE NO    EIGENVALUE                       FREQUENCY   
                                     REAL PART            IMAGINARY PART
                           (RAD/TIME)      (CYCLES/TIME     (RAD/TIME)

      1  -0.3295854E-04   0.0000000E+00   0.0000000E+00   0.5740953E-02
      2  -0.1838898E-04   0.0000000E+00   0.0000000E+00   0.4288238E-02
      3   0.1417850E-04   0.3765435E-02   0.5992869E-03   0.0000000E+00
      4   0.3644743E-05   0.1909121E-02   0.3038494E-03   0.0000000E+00
      5   0.1081399E-05   0.1039903E-02   0.1655061E-03   0.0000000E+00
      6   0.5188693E-05   0.2277870E-02   0.3625343E-03   0.0000000E+00
      7   0.2741350E+07   0.1655702E+04   0.2635132E+03   0.0000000E+00
      8   0.2742246E+07   0.1655973E+04   0.2635562E+03   0.0000000E+00
      9   0.2018842E+08   0.4493152E+04   0.7151074E+03   0.0000000E+00
     10   0.2021218E+08   0.4495795E+04   0.7155281E+03   0.0000000E+00
     11   0.7427730E+08   0.8618428E+04   0.1371665E+04   0.0000000E+00
     12   0.7445481E+08   0.8628720E+04   0.1373303E+04   0.0000000E+00

     P A R T I C I P A T I O N   F A C T O R S

MODE NO.   X-COMPONENT     Y-COMPONENT     Z-COMPONENT     X-ROTATION      Y-ROTATION      Z-ROTATION

      1  -0.1543658E+00   0.2540670E+00   0.1871929E+01   0.1167795E+00  -0.5712721E+00  -0.5697237E-01
)";

TEST(Calculix, EigenvalueTableAndRigidModes) {
  absl::StatusOr<std::vector<double>> e = ParseEigenvalues(kDat);
  ASSERT_TRUE(e.ok()) << e.status();
  ASSERT_EQ(e->size(), 12u);
  EXPECT_DOUBLE_EQ((*e)[0], -0.3295854E-04);
  EXPECT_DOUBLE_EQ((*e)[11], 0.7445481E+08);
  const Modes m = SplitRigidModes(*e, 6);
  EXPECT_EQ(m.rigid, 6);
  ASSERT_EQ(m.elastic_hz.size(), 6u);
  EXPECT_NEAR(m.elastic_hz[0], 263.5132, 1e-3);  // the table's cycles/time column
  EXPECT_NEAR(m.elastic_hz[5], 1373.303, 1e-2);
  // Asking for fewer keeps the lowest.
  EXPECT_EQ(SplitRigidModes(*e, 2).elastic_hz.size(), 2u);
  EXPECT_FALSE(ParseEigenvalues("no table here").ok());
}

TEST(Calculix, DeckHasQuadraticTetrahedra) {
  const TetMesh m = BoxTets(1, 1, 1);
  std::ostringstream out;
  const int nodes = ModalDeck(m, Material{}, 12, out);
  const std::string deck = out.str();
  // 8 corners + 19 edges (12 of the cube, 6 face diagonals, 1 main diagonal).
  EXPECT_EQ(nodes, 8 + 19);
  EXPECT_HAS(deck, "*ELEMENT, TYPE=C3D10, ELSET=EALL\n1, 1, ");
  EXPECT_HAS(deck, "*ELASTIC\n210000000000, 0.3\n*DENSITY\n7850\n");
  EXPECT_HAS(deck, "*FREQUENCY\n12\n*END STEP\n");
}

TEST(ClosedSolid, OpenAndInsideOutSurfacesAreRefused) {
  RawMesh box = testing::MakeBox({1, 1, 1}, {2, 2, 2});
  EXPECT_TRUE(CheckClosedSolid(box).ok());
  RawMesh open = box;
  open.triangles.resize(open.triangles.size() - 6);  // one square gone
  const absl::Status s = CheckClosedSolid(open);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_HAS(s.message(), "not closed (4 boundary edges)");
  RawMesh inverted = box;
  for (size_t f = 0; f < inverted.num_faces(); ++f)
    std::swap(inverted.triangles[3 * f + 1], inverted.triangles[3 * f + 2]);
  EXPECT_HAS(CheckClosedSolid(inverted).message(), "no positive volume");
  // Two boxes through each other: closed and outward, but they bound no solid.
  RawMesh crossing = box;
  testing::Append(crossing, testing::MakeBox({1, 1, 1}, {2, 2, 2}), {0.3f, 0.3f, 0.3f});
  const absl::Status c = CheckClosedSolid(crossing);
  EXPECT_EQ(c.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_HAS(c.message(), "the surface intersects itself: ");
  EXPECT_HAS(c.message(), " face pairs cross (the first: faces ");
  EXPECT_HAS(c.message(), "tetgen cannot mesh it");
  // A facet turned over onto its neighbours (a fold repair could not undo): refused by name.
  const absl::Status folded = CheckClosedSolid(testing::CubeWithAFoldOnTop());
  EXPECT_EQ(folded.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_HAS(folded.message(),
             "the surface has folded faces: 3 face pairs lie on each other in "
             "their plane, one of each turned over (the first: faces 10 and 11");
  EXPECT_HAS(folded.message(), "tetgen cannot mesh faces lying on each other");
  // A block standing on the box, exported apart (the contact triangulated twice): refused as
  // overlapping faces with the contact's area, before tetgen aborts on it.
  RawMesh stacked = box;
  testing::Append(stacked, testing::MakeBox({0.5, 0.5, 1}, {3, 3, 2}), {0.25f, 0.25f, 1.0f});
  EXPECT_TRUE(CheckClosedSolid(stacked).ok());
  // Tilted and rounded to float, the block's sides poke through the box's top by that rounding:
  // still a contact.
  EXPECT_TRUE(CheckClosedSolid(testing::TurnedSkew(stacked)).ok());
  // Standing on the box's top corner quarter, the block has two corners on the box's vertices;
  // welded there it is one body with the box, which tetgen would have to mesh whole: refused,
  // naming the overlap.
  RawMesh joined = box;
  testing::Append(joined, testing::MakeBox({0.5, 0.5, 1}, {3, 3, 2}), {0.5f, 0.5f, 1.0f});
  int welded = 0;
  for (uint32_t& v : joined.triangles)
    for (uint32_t w = 0; w < box.num_vertices() && v >= box.num_vertices(); ++w)
      if (std::equal(&joined.positions[3 * v], &joined.positions[3 * v] + 3,
                     &joined.positions[3 * w])) {
        v = w;
        ++welded;
      }
  ASSERT_GT(welded, 0);
  const absl::Status o = CheckClosedSolid(joined);
  EXPECT_EQ(o.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_HAS(o.message(), "the surface has overlapping faces, some within one body");
  EXPECT_HAS(o.message(), " face pairs overlap in their plane, over an area of ");
  EXPECT_HAS(o.message(), "tetgen cannot mesh overlapping faces");
  // The block turned inside out (no cavity of the box: it lies outside it) is refused.
  RawMesh inverted_block = box;
  RawMesh block = testing::MakeBox({0.5, 0.5, 1}, {3, 3, 2});
  for (size_t f = 0; f < block.num_faces(); ++f)
    std::swap(block.triangles[3 * f + 1], block.triangles[3 * f + 2]);
  testing::Append(inverted_block, block, {0.25f, 0.25f, 1.0f});
  EXPECT_HAS(CheckClosedSolid(inverted_block).message(),
             "touching bodies, one of which encloses no positive volume");
}

class ChildProcess : public testing::TempDirTest {};

TEST_F(ChildProcess, ExitCodeAndOutput) {
  absl::StatusOr<std::string> sh = FindOnPath("sh", "/nonexistent:/bin:/usr/bin");
  ASSERT_TRUE(sh.ok()) << sh.status();
  EXPECT_FALSE(FindOnPath("femsimp-no-such-tool", "/bin:/usr/bin").ok());
  ChildRun run{.command = "sh",
               .argv = {*sh, "-c", "echo first; echo; echo \"$FECHECK_X\" >&2; exit 3"},
               .dir = dir_,
               .log_path = Path("sh.log"),
               .env = {"FECHECK_X=second"}};
  absl::StatusOr<ChildExit> exit = RunChild(run);
  ASSERT_TRUE(exit.ok()) << exit.status();
  EXPECT_EQ(exit->exit_code, 3);
  EXPECT_EQ(exit->Describe(), "exit code 3");
  EXPECT_EQ(LastLines(Path("sh.log"), 5), "first\nsecond");
  EXPECT_EQ(LastLines(Path("sh.log"), 1), "second");
}

TEST_F(ChildProcess, CancelKillsTheChild) {
  absl::StatusOr<std::string> sh = FindOnPath("sh", "/bin:/usr/bin");
  ASSERT_TRUE(sh.ok());
  // The child writes its pid, then would sleep for a minute; the cancel comes once the pid is
  // there.
  const std::string pid_file = Path("pid");
  ChildRun run{.command = "sh",
               .argv = {*sh, "-c", "echo $$ > pid.tmp && mv pid.tmp pid && exec sleep 60"},
               .dir = dir_,
               .log_path = Path("sh.log"),
               .cancelled = [&] { return fs::exists(pid_file); }};
  absl::StatusOr<ChildExit> exit = RunChild(run);
  EXPECT_EQ(exit.status().code(), absl::StatusCode::kCancelled);
  pid_t pid = 0;
  std::ifstream(pid_file) >> pid;
  ASSERT_GT(pid, 0);
  EXPECT_EQ(kill(pid, 0), -1) << "the child " << pid << " is still there";
  EXPECT_EQ(errno, ESRCH);
}

TEST(TempDir, RemovedWithItsFiles) {
  std::string path;
  {
    absl::StatusOr<TempDir> dir = TempDir::Create();
    ASSERT_TRUE(dir.ok()) << dir.status();
    path = dir->path();
    std::ofstream(dir->File("x")) << "x";
    EXPECT_TRUE(fs::exists(dir->File("x")));
  }
  EXPECT_FALSE(fs::exists(path));
}

// --- End to end, with tetgen and CalculiX ---

// Steel, 1 m long, 20 mm square section: slender (L/h = 50), so that Euler-Bernoulli theory is
// within 0.8 % of the solid for the first three bending modes (docs/FIDELITY.md, "FE check").
constexpr double kL = 1.0, kH = 0.02;
RawMesh Beam(double scale = 1.0) {
  return testing::MakeBox({kL * scale, kH * scale, kH * scale}, {50, 2, 2});
}

// Free-free Euler-Bernoulli beam: f_n = (beta_n L)^2 / (2 pi L^2) sqrt(E I / (rho A)).
double EulerBernoulliHz(double beta_l, const Material& m) {
  const double area = kH * kH, inertia = kH * kH * kH * kH / 12;
  return beta_l * beta_l / (2 * std::numbers::pi * kL * kL) *
         std::sqrt(m.youngs_modulus * inertia / (m.density * area));
}

// A part read far from the origin is held relative to its local origin (engine/local_origin.h):
// tetgen and CalculiX run on the relative positions, the centroid is reported where the file has
// it, in metres (unit scale: mm here).
TEST(FeCheck, FarPartsCentroidIsWhereTheFileHasIt) {
  SKIP_WITHOUT_FE_TOOLS();
  FeCheckOptions options;
  options.unit_scale = 1e-3;
  RawMesh beam = Beam(1e3);  // 1000 x 20 x 20 mm
  beam.origin = {1e6, 2e6, -3e5};
  absl::StatusOr<SolidFigures> f = AnalyseSolid(beam, "beam", options, 0.0);
  ASSERT_TRUE(f.ok()) << f.status();
  EXPECT_NEAR(f->centroid[0], 1e3 + kL / 2, 1e-6);
  EXPECT_NEAR(f->centroid[1], 2e3 + kH / 2, 1e-6);
  EXPECT_NEAR(f->centroid[2], -3e2 + kH / 2, 1e-6);
  EXPECT_NEAR(f->volume, kL * kH * kH, 1e-6 * kL * kH * kH);
}

// A unit box with a cavity (a cube's surface of side 0.5 inside, facing into it).
RawMesh HollowCube() {
  RawMesh hollow = testing::MakeBox({1, 1, 1}, {4, 4, 4});
  const RawMesh cavity = testing::MakeBox({0.5, 0.5, 0.5}, {2, 2, 2});
  const uint32_t base = uint32_t(hollow.num_vertices());
  for (size_t i = 0; i < cavity.positions.size(); ++i)
    hollow.positions.push_back(cavity.positions[i] + 0.25f);
  for (size_t f = 0; f < cavity.num_faces(); ++f)  // turned to face into the cavity
    hollow.triangles.insert(hollow.triangles.end(),
                            {base + cavity.triangles[3 * f], base + cavity.triangles[3 * f + 2],
                             base + cavity.triangles[3 * f + 1]});
  return hollow;
}

// tetgen would fill the cavity with tetrahedra unless told it is a hole, and the solid would
// weigh as a full box.
TEST(FeCheck, CavityIsNotMeshed) {
  SKIP_WITHOUT_FE_TOOLS();
  const RawMesh hollow = HollowCube();
  absl::StatusOr<SolidFigures> f = AnalyseSolid(hollow, "hollow", FeCheckOptions{}, 0.0);
  ASSERT_TRUE(f.ok()) << f.status();
  EXPECT_NEAR(f->volume, 1.0 - 0.125, 1e-6);
  const double density = f->mass / f->volume;
  // A cube of side a and volume V has a moment V a^2 / 6 about every axis through its centre.
  const double moment = density * (1.0 / 6 - 0.125 * 0.25 / 6);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f->principal_moments[k] / moment, 1.0, 1e-6) << k;
  EXPECT_EQ(f->components, 1);
  EXPECT_EQ(f->rigid_modes, 6);
}

// The hollow box with a core in its cavity that shares the cavity's whole surface, written facing
// out of the core (femsimp's output of a body inside another): the two are one solid, bonded,
// meshed whole as a full box with one body's six rigid-body modes.
TEST(FeCheck, ABodyInsideAnotherSharingItsSurfaceIsMeshedBonded) {
  SKIP_WITHOUT_FE_TOOLS();
  RawMesh cored = HollowCube();
  const uint32_t first =
      uint32_t(cored.num_vertices() - testing::MakeBox({0.5, 0.5, 0.5}, {2, 2, 2}).num_vertices());
  const size_t walls = cored.num_faces() - testing::MakeBox({0.5, 0.5, 0.5}, {2, 2, 2}).num_faces();
  const size_t faces = cored.num_faces();
  for (size_t f = walls; f < faces; ++f) {
    const uint32_t* t = &cored.triangles[3 * f];
    ASSERT_GE(std::min({t[0], t[1], t[2]}), first);
    const uint32_t a = t[0], b = t[2], c = t[1];
    cored.triangles.insert(cored.triangles.end(), {a, b, c});
  }
  ASSERT_TRUE(CheckClosedSolid(cored).ok()) << CheckClosedSolid(cored);
  absl::StatusOr<SolidFigures> f = AnalyseSolid(cored, "cored", FeCheckOptions{}, 0.0);
  ASSERT_TRUE(f.ok()) << f.status();
  EXPECT_NEAR(f->volume, 1.0, 1e-6);
  const double moment = f->mass / f->volume / 6;  // a unit cube's, about its centre
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f->principal_moments[k] / moment, 1.0, 1e-6) << k;
  EXPECT_EQ(f->components, 1);
  EXPECT_EQ(f->rigid_modes, 6);
}

// A block standing on the hollow box, exported apart (the contact's facets overlap, no vertex
// shared): tetgen refuses the whole, so each body is meshed on its own, the cavity with the box
// that holds it; the two are not bonded (twelve rigid-body modes).
TEST(FeCheck, TouchingBodiesAreMeshedApart) {
  SKIP_WITHOUT_FE_TOOLS();
  RawMesh bodies = HollowCube();
  testing::Append(bodies, testing::MakeBox({0.5, 0.5, 1}, {2, 2, 2}), {0.2f, 0.2f, 1.0f});
  ASSERT_GT(FindCrossings(bodies).overlaps.pairs, 0u);
  absl::StatusOr<SolidFigures> f = AnalyseSolid(bodies, "bodies", FeCheckOptions{}, 0.0);
  ASSERT_TRUE(f.ok()) << f.status();
  EXPECT_NEAR(f->volume, 1.0 - 0.125 + 0.25, 1e-6);
  EXPECT_EQ(f->bodies_meshed_apart, 2);
  EXPECT_EQ(f->components, 2);
  EXPECT_EQ(f->rigid_modes, 12);
  // A hollow island in the cavity: its own cavity goes with it (the innermost shell around it),
  // not with the box.
  RawMesh island = testing::MakeBox({0.3, 0.3, 0.3}, {2, 2, 2});
  const RawMesh hole = testing::MakeBox({0.1, 0.1, 0.1}, {1, 1, 1});
  const uint32_t first = uint32_t(island.num_vertices());
  for (size_t i = 0; i < hole.positions.size(); ++i)
    island.positions.push_back(hole.positions[i] + 0.1f);
  for (size_t t = 0; t < hole.num_faces(); ++t)
    island.triangles.insert(island.triangles.end(),
                            {first + hole.triangles[3 * t], first + hole.triangles[3 * t + 2],
                             first + hole.triangles[3 * t + 1]});
  testing::Append(bodies, island, {0.35f, 0.35f, 0.35f});
  f = AnalyseSolid(bodies, "bodies", FeCheckOptions{}, 0.0);
  ASSERT_TRUE(f.ok()) << f.status();
  EXPECT_NEAR(f->volume, 1.0 - 0.125 + 0.25 + 0.027 - 0.001, 1e-6);
  EXPECT_EQ(f->bodies_meshed_apart, 3);
  EXPECT_EQ(f->components, 3);
  EXPECT_EQ(f->rigid_modes, 18);
}

TEST(FeCheck, FreeFreeBeamMatchesBeamTheory) {
  SKIP_WITHOUT_FE_TOOLS();
  const FeCheckOptions options;
  absl::StatusOr<SolidFigures> f = AnalyseSolid(Beam(), "beam", options, 0.0);
  ASSERT_TRUE(f.ok()) << f.status();
  const Material& m = options.material;
  // Mass properties from the tetrahedra: exact up to the float coordinates of the surface.
  const double volume = kL * kH * kH, mass = m.density * volume;
  EXPECT_NEAR(f->volume, volume, 1e-6 * volume);
  EXPECT_NEAR(f->mass, mass, 1e-6 * mass);
  EXPECT_NEAR(f->centroid[0], kL / 2, 1e-6);
  EXPECT_NEAR(f->centroid[1], kH / 2, 1e-6);
  EXPECT_NEAR(f->centroid[2], kH / 2, 1e-6);
  EXPECT_NEAR(f->principal_moments[0], mass * 2 * kH * kH / 12, 1e-5 * mass * kH * kH);
  EXPECT_NEAR(f->principal_moments[1], mass * (kL * kL + kH * kH) / 12, 1e-6 * mass);
  EXPECT_NEAR(f->principal_moments[2], mass * (kL * kL + kH * kH) / 12, 1e-6 * mass);
  EXPECT_EQ(f->components, 1);
  EXPECT_EQ(f->rigid_modes, 6);
  std::printf("beam: %lld tetrahedra, %lld solver nodes\n", static_cast<long long>(f->tetrahedra),
              static_cast<long long>(f->solver_nodes));
  // The square section bends alike in y and z: the six lowest elastic modes are the first three
  // bending modes, twice each (torsion comes at ~1470 Hz, tension at ~2590 Hz).
  ASSERT_EQ(f->frequencies_hz.size(), 6u);
  const double beta_l[3] = {4.73004, 7.85320, 10.99561};
  // Shear and rotary inertia (Timoshenko) put the solid below the Euler-Bernoulli beam by
  // 0.14 %, 0.41 %, 0.78 % (measured with a 4x finer mesh); this mesh adds at most +0.05 %.
  const double tolerance[3] = {0.003, 0.006, 0.010};
  for (int n = 0; n < 3; ++n) {
    const double want = EulerBernoulliHz(beta_l[n], m);
    for (int k = 0; k < 2; ++k) {
      const double got = f->frequencies_hz[2 * n + k];
      std::printf("bending mode %d (%c): %.3f Hz, Euler-Bernoulli %.3f Hz, %+.3f %%\n", n + 1,
                  k ? 'z' : 'y', got, want, 100 * (got / want - 1));
      EXPECT_NEAR(got / want, 1.0, tolerance[n]) << "bending mode " << n + 1;
    }
    EXPECT_NEAR(f->frequencies_hz[2 * n + 1] / f->frequencies_hz[2 * n], 1.0, 1e-3)
        << "bending mode " << n + 1 << " differs between the two planes";
  }
}

// The discretisation error of the mesh above: the same beam with twice the elements along every
// edge (several times slower, hence not part of the run; docs/FIDELITY.md quotes its output).
TEST(FeCheck, DISABLED_BeamOnAFinerMesh) {
  SKIP_WITHOUT_FE_TOOLS();
  const std::array<int, 3> cells[2] = {{50, 2, 2}, {100, 4, 4}};
  for (const std::array<int, 3>& c : cells) {
    absl::StatusOr<SolidFigures> f =
        AnalyseSolid(testing::MakeBox({kL, kH, kH}, c), "beam", FeCheckOptions{}, 0.0);
    ASSERT_TRUE(f.ok()) << f.status();
    std::printf("%d x %d x %d cells, %lld tetrahedra:", c[0], c[1], c[2],
                static_cast<long long>(f->tetrahedra));
    for (double hz : f->frequencies_hz) std::printf(" %.3f", hz);
    std::printf(" Hz\n");
  }
}

TEST(FeCheck, IdenticalMeshesGiveNoDifference) {
  SKIP_WITHOUT_FE_TOOLS();
  const RawMesh box = testing::MakeBox({1, 0.2, 0.1}, {10, 2, 1});
  absl::StatusOr<FeCheckReport> r = RunFeCheck(box, box, FeCheckOptions{});
  ASSERT_TRUE(r.ok()) << r.status();
  const FeDifferences d = Compare(r->original, r->simplified);
  EXPECT_EQ(d.volume, 0.0);
  EXPECT_EQ(d.centroid_shift, 0.0);
  EXPECT_EQ(d.worst_moment, 0.0);
  ASSERT_EQ(d.frequencies.size(), 6u);
  EXPECT_EQ(d.worst_frequency, 0.0);
  EXPECT_GT(r->original.frequencies_hz[0], 0.0);
}

// The same beam in millimetres with --unit-scale 0.001 is the same solid, and a coarser
// surface of it is nearly so.
TEST(FeCheck, UnitScaleAndACoarserMesh) {
  SKIP_WITHOUT_FE_TOOLS();
  FeCheckOptions mm;
  mm.unit_scale = 0.001;
  const RawMesh coarse = testing::MakeBox({1000 * kL, 1000 * kH, 1000 * kH}, {25, 1, 1});
  absl::StatusOr<FeCheckReport> r = RunFeCheck(Beam(1000), coarse, mm);
  ASSERT_TRUE(r.ok()) << r.status();
  absl::StatusOr<SolidFigures> metres = AnalyseSolid(Beam(), "beam", FeCheckOptions{}, 0.0);
  ASSERT_TRUE(metres.ok()) << metres.status();
  EXPECT_NEAR(r->original.volume / metres->volume, 1.0, 1e-6);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(r->original.principal_moments[k] / metres->principal_moments[k], 1.0, 1e-5);
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(r->original.frequencies_hz[i] / metres->frequencies_hz[i], 1.0, 1e-5);
  const FeDifferences d = Compare(r->original, r->simplified);
  EXPECT_NEAR(d.volume, 0.0, 1e-6);
  EXPECT_GT(d.worst_frequency, 0.0);   // one element across the section is stiffer...
  EXPECT_LT(d.worst_frequency, 0.01);  // ...but quadratic tetrahedra stay close
}

TEST(FeCheck, OpenSurfaceIsRefusedBeforeAnyToolRuns) {
  SKIP_WITHOUT_FE_TOOLS();
  RawMesh open = testing::MakeBox({1, 1, 1}, {2, 2, 2});
  open.triangles.resize(open.triangles.size() - 3);
  absl::StatusOr<FeCheckReport> r = RunFeCheck(testing::MakeBox({1, 1, 1}, {2, 2, 2}), open, {});
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_HAS(r.status().message(), "simplified: the surface is not closed (3 boundary edges)");
}

TEST(FeCheck, SelfIntersectingSurfaceIsRefusedBeforeAnyToolRuns) {
  SKIP_WITHOUT_FE_TOOLS();
  // Two closed tetrahedra that pass through each other: closed and outward, but no solid.
  RawMesh two = testing::Tetrahedron();
  RawMesh shifted = testing::Tetrahedron();
  const uint32_t n = static_cast<uint32_t>(two.num_vertices());
  for (size_t i = 0; i < shifted.positions.size(); ++i)
    two.positions.push_back(shifted.positions[i] + 0.2f);
  for (uint32_t v : shifted.triangles) two.triangles.push_back(v + n);
  int stages = 0;
  FeCheckControl control;
  control.on_stage = [&](const FeStage&) { ++stages; };
  absl::StatusOr<FeCheckReport> r = RunFeCheck(Beam(), two, {}, control);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_HAS(r.status().message(), "simplified: the surface intersects itself: ");
  EXPECT_EQ(stages, 0);  // not even the original's tetgen run
}

// PATH without the tools: the message names the missing ones and their Debian packages.
TEST(FeCheck, MissingToolNamesItsDebianPackage) {
  SKIP_WITHOUT_FE_TOOLS();
  const std::string saved = std::getenv("PATH");
  const std::string only_tetgen = testing::MakeTempDir("fecheck_path");
  absl::StatusOr<std::string> tetgen = LocateTool(kTetgen);
  ASSERT_TRUE(tetgen.ok());
  fs::create_symlink(*tetgen, only_tetgen + "/tetgen");
  const RawMesh box = testing::MakeBox({1, 1, 1}, {1, 1, 1});

  setenv("PATH", "/nonexistent", 1);
  absl::StatusOr<FeCheckReport> none = RunFeCheck(box, box, {});
  setenv("PATH", only_tetgen.c_str(), 1);
  absl::StatusOr<FeCheckReport> no_ccx = RunFeCheck(box, box, {});
  setenv("PATH", saved.c_str(), 1);
  fs::remove_all(only_tetgen);

  EXPECT_EQ(none.status().code(), absl::StatusCode::kNotFound);
  EXPECT_HAS(none.status().message(), "tetgen (Debian package tetgen)");
  EXPECT_HAS(none.status().message(), "ccx (Debian package calculix-ccx)");
  EXPECT_EQ(no_ccx.status().code(), absl::StatusCode::kNotFound);
  EXPECT_HAS(no_ccx.status().message(), "not found on PATH: ccx (Debian package calculix-ccx)");
}

// A cancel while CalculiX runs kills it and leaves no temporary directory behind.
TEST(FeCheck, CancelStopsTheSolverAndCleansUp) {
  SKIP_WITHOUT_FE_TOOLS();
  const std::string tmp = testing::MakeTempDir("fecheck_tmpdir");
  setenv("TMPDIR", tmp.c_str(), 1);
  bool solver_started = false;
  FeCheckControl control;
  control.on_stage = [&](const FeStage& s) {
    if (s.text.find("CalculiX") != std::string::npos) solver_started = true;
  };
  control.cancelled = [&] { return solver_started; };
  absl::StatusOr<FeCheckReport> r = RunFeCheck(Beam(), Beam(), {}, control);
  unsetenv("TMPDIR");
  EXPECT_TRUE(solver_started);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kCancelled) << r.status();
  EXPECT_HAS(r.status().message(), "original: ccx cancelled");
  EXPECT_TRUE(fs::is_empty(tmp)) << "left in " << tmp;
  fs::remove_all(tmp);
}

}  // namespace
}  // namespace femsimp::fecheck
