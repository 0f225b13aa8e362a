// The kernel's rules one at a time, on hand-made proposals: each is a unit that can be judged
// without a mesh, a port or the other rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/rule.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

std::vector<std::string> Names(const RuleSet& set, RuleStage stage) {
  std::vector<std::string> names;
  for (const CollapseRule* r : set.stage(stage)) names.push_back(RejectName(r->reason()));
  return names;
}

using Strings = std::vector<std::string>;

TEST(RuleSet, RulesFollowTheOptions) {
  SimplifyOptions o;
  RuleSetup setup;
  const RuleSet paper = RuleSet::Build(o, setup);
  EXPECT_EQ(Names(paper, RuleStage::kDirections), Strings({"feature"}));
  EXPECT_EQ(Names(paper, RuleStage::kShape),
            Strings({"degenerate", "fold_over", "min_angle", "normal_deviation"}));
  EXPECT_EQ(Names(paper, RuleStage::kTopology), Strings({"link_condition", "valence", "feature"}));
  EXPECT_TRUE(paper.stage(RuleStage::kScreen).empty());
  EXPECT_TRUE(paper.stage(RuleStage::kFidelity).empty());
  EXPECT_TRUE(paper.stage(RuleStage::kBudget).empty());
  EXPECT_FALSE(paper.reads_face_attrs());

  o.topology_only = true;
  EXPECT_EQ(Names(RuleSet::Build(o, setup), RuleStage::kShape),
            Strings({"degenerate", "fold_over"}));
  o.topology_only = false;

  // At 0 degrees no angle is too small: the rule is left out, in both forms.
  o.min_angle_deg = 0;
  for (const bool strict : {false, true}) {
    o.strict_min_angle = strict;
    EXPECT_EQ(Names(RuleSet::Build(o, setup), RuleStage::kShape),
              Strings({"degenerate", "fold_over", "normal_deviation"}));
  }

  SimplifyOptions f;
  f.max_volume_change = 0.01;
  f.max_centroid_shift = 0.01;
  setup.tolerance = 0.5f;
  setup.fields = 1;
  setup.closed = true;  // the volume budget applies to closed meshes only
  const MassProperties mass{1.0, {0, 0, 0}, {}};
  const FieldResultants resultants;
  setup.mass = &mass;
  setup.resultants = &resultants;
  const RuleSet fidelity = RuleSet::Build(f, setup);
  EXPECT_EQ(Names(fidelity, RuleStage::kFidelity),
            Strings({"tolerance", "volume", "centroid", "field_resultant"}));
  EXPECT_EQ(Names(fidelity, RuleStage::kScreen), Strings({"tolerance"}));
  EXPECT_EQ(Names(fidelity, RuleStage::kBudget),
            Strings({"volume", "centroid", "field_resultant"}));
  EXPECT_TRUE(fidelity.reads_face_attrs());
  EXPECT_TRUE(fidelity.tracks_mass());
}

using testing::RegularFan;

const CollapseRule& Only(const RuleSet& set, RuleStage stage, Reject reason) {
  for (const CollapseRule* r : set.stage(stage))
    if (r->reason() == reason) return *r;
  ADD_FAILURE() << "no rule " << RejectName(reason);
  return *set.stage(stage).front();
}

TEST(Rules, MinAngleJudgesTheNewTriangles) {
  // Collapsing the centre of a regular hexagon onto a corner fans the hexagon from that
  // corner: its new triangles have angles of 30, 60 and 90 degrees.
  const Ring fan = RegularFan(6);
  CollapseProposal p;
  p.fan = &fan;
  p.target = 0;
  p.geometry.Build(fan, 0);
  ASSERT_EQ(p.geometry.faces, 4);
  for (double min_angle : {25.0, 35.0}) {
    SimplifyOptions o;
    o.min_angle_deg = min_angle;
    const RuleSet set = RuleSet::Build(o, RuleSetup{});
    const Verdict v = Only(set, RuleStage::kShape, Reject::kMinAngle).Check(RuleStage::kShape, p);
    EXPECT_EQ(v, min_angle < 30 ? Verdict::kPass : Verdict::kReject) << min_angle;
  }
}

// V almost on neighbour 0: its fan holds two slivers. Collapsing it onto neighbour 0 fans the
// hexagon from there (smallest angle 30 degrees): below a 45-degree threshold, so the strict rule
// refuses; no worse than the slivers it replaces, so the relaxed (default) rule accepts.
TEST(Rules, RelaxedMinAngleLetsSliversImprove) {
  Ring fan = RegularFan(6);
  fan.center_pos = {0.98f, 0.0f, 0.0f};
  CollapseProposal p;
  p.fan = &fan;
  p.target = 0;
  p.geometry.Build(fan, 0);
  for (bool strict : {true, false}) {
    SimplifyOptions o;
    o.min_angle_deg = 45;
    o.strict_min_angle = strict;
    const RuleSet set = RuleSet::Build(o, RuleSetup{});
    EXPECT_EQ(Only(set, RuleStage::kShape, Reject::kMinAngle).Check(RuleStage::kShape, p),
              strict ? Verdict::kReject : Verdict::kPass)
        << (strict ? "strict" : "relaxed");
  }
}

TEST(Rules, DegenerateAndFoldOverAcceptAFlatFanCollapse) {
  const Ring fan = RegularFan(6);
  CollapseProposal p;
  p.fan = &fan;
  p.target = 2;
  p.geometry.Build(fan, 2);
  Reject refused = Reject::kCount;
  EXPECT_EQ(RuleSet::Build(SimplifyOptions{}, RuleSetup{}).Check(RuleStage::kShape, p, &refused),
            Verdict::kPass);
  // A link vertex pulled in next to V makes the link concave: collapsing V onto neighbour 0
  // turns the new triangle over that vertex.
  Ring bent = fan;
  bent.pos[1] = {0.2f, 0.1f, 0.0f};
  p.fan = &bent;
  p.geometry.Build(bent, 0);
  SimplifyOptions topology_only;
  topology_only.topology_only = true;
  EXPECT_EQ(RuleSet::Build(topology_only, RuleSetup{}).Check(RuleStage::kShape, p, &refused),
            Verdict::kReject);
  EXPECT_EQ(refused, Reject::kFoldOver);
}

TEST(Rules, LinkConditionRefusesJoiningConnectedVertices) {
  const Ring fan = RegularFan(4);  // neighbours 1, 2, 3, 4
  Ring vd_fan;                     // Vd = 1: neighbours 0 (V), 2 and 4 (opposite), 5, 6
  vd_fan.faces = 5;
  const uint32_t around[] = {0, 4, 5, 6, 2};
  for (int i = 0; i < 5; ++i) vd_fan.nbr[i] = around[i];
  CollapseProposal p;
  p.fan = &fan;
  p.target = 0;
  p.target_fan = &vd_fan;
  p.deleted = 2;
  p.opposite[0] = 2;
  p.opposite[1] = 4;
  const RuleSet set = RuleSet::Build(SimplifyOptions{}, RuleSetup{});
  const CollapseRule& link = Only(set, RuleStage::kTopology, Reject::kLink);
  EXPECT_EQ(link.Check(RuleStage::kTopology, p), Verdict::kPass);
  vd_fan.nbr[3] = 3;  // Vd already connected to V's neighbour 3: the collapse would pinch
  EXPECT_EQ(link.Check(RuleStage::kTopology, p), Verdict::kReject);
}

class FakeReader final : public NeighbourhoodReader {
 public:
  FakeReader(int faces, bool boundary, bool stale)
      : faces_(faces), boundary_(boundary), stale_(stale) {}
  bool CountFan(uint32_t, int limit, int* faces, bool* boundary) override {
    *faces = std::min(faces_, limit);
    *boundary = boundary_;
    return !stale_;
  }
  int Neighbours(uint32_t, uint32_t*) override { return stale_ ? -1 : 0; }

 private:
  int faces_;
  bool boundary_, stale_;
};

TEST(Rules, ValenceKeepsATetrahedronAndTheLastFace) {
  const RuleSet set = RuleSet::Build(SimplifyOptions{}, RuleSetup{});
  const CollapseRule& valence = Only(set, RuleStage::kTopology, Reject::kValence);
  CollapseProposal p;
  p.deleted = 1;
  p.opposite[0] = 7;
  struct Case {
    int faces;
    bool boundary, stale;
    Verdict expected;
  };
  for (const Case& c :
       {Case{3, false, false, Verdict::kReject}, Case{4, false, false, Verdict::kPass},
        Case{1, true, false, Verdict::kReject}, Case{2, true, false, Verdict::kPass},
        Case{9, false, true, Verdict::kStale}}) {
    FakeReader reader(c.faces, c.boundary, c.stale);
    p.reader = &reader;
    EXPECT_EQ(valence.Check(RuleStage::kTopology, p), c.expected) << c.faces << c.boundary;
  }
}

TEST(Rules, FeatureLineFixesCornersAndKeepsVerticesOnTheirLine) {
  RuleSetup setup;
  setup.cos_feature = std::cos(30 * std::numbers::pi / 180);
  const RuleSet set = RuleSet::Build(SimplifyOptions{}, setup);
  const CollapseRule& feature = Only(set, RuleStage::kDirections, Reject::kFeature);
  Ring fan = RegularFan(6);
  Directions free;
  feature.Restrict(fan, &free);
  EXPECT_FALSE(free.fixed);
  EXPECT_FALSE(free.on_line());

  fan.feature[0] = fan.feature[3] = true;  // a straight line through neighbours 1 and 4
  Directions line;
  feature.Restrict(fan, &line);
  EXPECT_FALSE(line.fixed);
  EXPECT_TRUE(line.Allows(0) && line.Allows(3) && !line.Allows(1));
  EXPECT_EQ(line.LineOther(0), 3);

  fan.feature[3] = false;
  fan.feature[2] = true;  // turns by 120 degrees: a corner
  Directions corner;
  feature.Restrict(fan, &corner);
  EXPECT_TRUE(corner.fixed);
}

// The rules of a run on a closed mesh whose measures are `input` (the budget rules' ledger).
RuleSet ClosedMeshRules(const SimplifyOptions& o, const MassProperties& input,
                        const FieldResultants& resultants) {
  RuleSetup setup;
  setup.closed = true;
  setup.mass = &input;
  setup.resultants = &resultants;
  return RuleSet::Build(o, setup);
}

TEST(Rules, VolumeBudgetIsSpentAgainstTheInput) {
  SimplifyOptions o;
  o.max_volume_change = 0.01;
  const MassProperties input{100.0, {0, 0, 0}, {}};
  const FieldResultants none;
  const RuleSet set = ClosedMeshRules(o, input, none);
  const CollapseRule& volume = Only(set, RuleStage::kBudget, Reject::kVolume);
  const std::vector<DVec3> no_force;
  for (double spent : {0.5, -0.99, 1.01, -2.0}) {
    const MassProperties change{spent, {0, 0, 0}, {}};
    EXPECT_EQ(volume.WithinBudget(LedgerView{input, change, none, no_force}, CollapseDelta{}),
              std::fabs(spent) <= 1.0)
        << spent;
  }
}

// The inertia budget at share `allowed` of a closed part's input masses, judging totals alone.
class InertiaBudgetOf {
 public:
  InertiaBudgetOf(double allowed, const MassProperties& input)
      : options_(Options(allowed)),
        input_(input),
        set_(ClosedMeshRules(options_, input_, none_)),
        rule_(Only(set_, RuleStage::kBudget, Reject::kInertia)) {}
  bool Within(const MassProperties& spent) const {
    return rule_.WithinBudget(LedgerView{input_, spent, none_, no_force_}, CollapseDelta{});
  }

 private:
  static SimplifyOptions Options(double allowed) {
    SimplifyOptions o;
    o.max_inertia_change = allowed;
    return o;
  }
  const SimplifyOptions options_;
  const MassProperties input_;
  const FieldResultants none_;
  const std::vector<DVec3> no_force_;
  const RuleSet set_;
  const CollapseRule& rule_;
};

// The inertia budget: the input's moments are 4/15 each (the octahedron, second moment 2/15 on
// the diagonal about its centroid at the origin); 1 % lets each move by 4/1500.
TEST(Rules, InertiaBudgetBoundsTheChangeOfEveryPrincipalMoment) {
  MassProperties input{4.0 / 3.0, {0, 0, 0}, {}};
  input.second = Sym3{2.0 / 15, 2.0 / 15, 2.0 / 15, 0, 0, 0};
  const InertiaBudgetOf budget(0.01, input);
  const auto within = [&](const MassProperties& spent) { return budget.Within(spent); };
  const double allowed = 0.01 * 4.0 / 15.0;
  // A second moment change along one axis: InertiaOf has norm equal to it.
  MassProperties spent;
  spent.second = Sym3{0.9 * allowed, 0, 0, 0, 0, 0};
  EXPECT_TRUE(within(spent));
  spent.second = Sym3{0, 0, -1.1 * allowed, 0, 0, 0};
  EXPECT_FALSE(within(spent));
  // An off-diagonal change rotates the axes: its eigenvalues are +-xy.
  spent.second = Sym3{0, 0, 0, 0.9 * allowed, 0, 0};
  EXPECT_TRUE(within(spent));
  // A shifted centroid lowers the moments about it by up to |dm|^2 / M: dm = 0.03 gives 0.000675,
  // which on top of the 0.9 share above moves the smallest moment by more than 1 %.
  spent.moment = {0.03, 0, 0};
  EXPECT_FALSE(within(spent));
  // Losing the whole measure is never within.
  spent = MassProperties{-4.0 / 3.0, {0, 0, 0}, {}};
  EXPECT_FALSE(within(spent));
}

// The eigenvalues of a symmetric 3x3 matrix, ascending, in closed form (the trigonometric
// solution of the characteristic cubic): independent of the engine's Jacobi iteration.
std::array<double, 3> Eigenvalues(const Sym3& m) {
  const double q = m.trace() / 3;
  const double off = m.xy * m.xy + m.yz * m.yz + m.zx * m.zx;
  const double p2 =
      (m.xx - q) * (m.xx - q) + (m.yy - q) * (m.yy - q) + (m.zz - q) * (m.zz - q) + 2 * off;
  const double p = std::sqrt(p2 / 6);
  if (!(p > 0)) return {q, q, q};
  const Sym3 b{(m.xx - q) / p, (m.yy - q) / p, (m.zz - q) / p, m.xy / p, m.yz / p, m.zx / p};
  const double det = b.xx * (b.yy * b.zz - b.yz * b.yz) - b.xy * (b.xy * b.zz - b.yz * b.zx) +
                     b.zx * (b.xy * b.yz - b.yy * b.zx);
  const double phi = std::acos(std::clamp(det / 2, -1.0, 1.0)) / 3;
  const double largest = q + 2 * p * std::cos(phi);
  const double smallest = q + 2 * p * std::cos(phi + 2 * std::numbers::pi / 3);
  return {smallest, 3 * q - largest - smallest, largest};
}

// A slender part (moments 0.11, 1.01, 1.1): each moment keeps to its own share. Every random
// change the budget lets through keeps each principal moment, rank by rank, within F of its
// input value (the inertia about the moved centroid, computed here from the totals), and
// changes far above F times the smallest moment pass where they load only the larger ones.
TEST(Rules, InertiaBudgetKeepsEachMomentWithinItsOwnShare) {
  MassProperties input{1.0, {0, 0, 0}, {}};
  input.second = Sym3{1.0, 0.1, 0.01, 0, 0, 0};
  const std::array<double, 3> before = Eigenvalues(InertiaOf(input.second));
  const InertiaBudgetOf budget(0.01, input);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int passed = 0, beyond_smallest = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const double size = 0.03 * std::pow(10.0, -2.0 * (unit(rng) + 1) / 2);  // 3e-4 .. 3e-2
    MassProperties spent{0.05 * size * unit(rng), {0, 0, 0}, {}};
    spent.second = size * Sym3{unit(rng), unit(rng), unit(rng), unit(rng), unit(rng), unit(rng)};
    spent.moment = 0.3 * size * DVec3{unit(rng), unit(rng), unit(rng)};
    if (!budget.Within(spent)) continue;
    ++passed;
    const double measure = input.measure + spent.measure;
    const Sym3 after =
        InertiaOf(input.second + spent.second) - (1.0 / measure) * InertiaOf(Outer(spent.moment));
    const std::array<double, 3> moved = Eigenvalues(after);
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(std::fabs(moved[k] - before[k]), 0.01 * before[k] * (1 + 1e-9))
          << "trial " << trial << " moment " << k;
    const std::array<double, 3> change = Eigenvalues(InertiaOf(spent.second));
    beyond_smallest += std::max(-change[0], change[2]) > 0.01 * before[0];
  }
  EXPECT_GT(passed, 100);
  EXPECT_GT(beyond_smallest, 10);
  // The largest moment alone (I_zz by d: the second moment by diag(d, d, -d) / 2): 0.9 of its
  // own share passes, eight times what the smallest moment's share would allow; 1.1 does not.
  for (const double share : {0.9, 1.1}) {
    MassProperties spent;
    const double d = share * 0.01 * before[2];
    spent.second = Sym3{d / 2, d / 2, -d / 2, 0, 0, 0};
    EXPECT_EQ(budget.Within(spent), share < 1) << share;
  }
}

// A slender part turned about its largest moment's axis keeps every moment: the turn enters the
// test only to second order. 0.02 rad passes (a bound on the whole change, |D^-1/2 E D^-1/2|,
// is 0.054 there: five times the share); 0.05 rad, which moves 2 % of the largest moment onto the
// smallest one's axis, does not.
TEST(Rules, InertiaBudgetLetsASlenderPartTurn) {
  MassProperties input{1.0, {0, 0, 0}, {}};
  input.second = Sym3{1.0, 0.1, 0.01, 0, 0, 0};  // moments 0.11 (x), 1.01 (y), 1.1 (z)
  const InertiaBudgetOf budget(0.01, input);
  for (const double angle : {0.02, 0.05}) {
    const double c = std::cos(angle), s = std::sin(angle);
    const Sym3& j = input.second;
    const Sym3 turned{c * c * j.xx + s * s * j.yy,
                      s * s * j.xx + c * c * j.yy,
                      j.zz,
                      c * s * (j.xx - j.yy),
                      0,
                      0};
    MassProperties spent;
    spent.second = turned - j;
    EXPECT_EQ(budget.Within(spent), angle < 0.03) << angle;
  }
}

// J turned by `angle` about the unit `axis`: R J R^T.
Sym3 Turned(const Sym3& j, const DVec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  const DVec3& a = axis;
  const double r[3][3] = {{c + t * a.x * a.x, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y},
                          {t * a.x * a.y + s * a.z, c + t * a.y * a.y, t * a.y * a.z - s * a.x},
                          {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, c + t * a.z * a.z}};
  const double m[3][3] = {{j.xx, j.xy, j.zx}, {j.xy, j.yy, j.yz}, {j.zx, j.yz, j.zz}};
  double out[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) out[i][k] += r[i][p] * m[p][q] * r[k][q];
  return Sym3{out[0][0], out[1][1], out[2][2], out[0][1], out[1][2], out[2][0]};
}

// The deterministic rounds judge each winner's change scaled by their number and spend the mean
// (engine/rounds.h): the totals the budget accepts must be a convex set. Every mix of two
// accepted random totals is accepted; half of them turn the part, which keeps its moments while
// two different turns' mean does not (a test of the moments themselves accepts both turns and
// refuses their mean).
TEST(Rules, InertiaBudgetAcceptsAConvexSetOfTotals) {
  MassProperties input{1.0, {0, 0, 0}, {}};
  input.second = Sym3{1.0, 0.1, 0.01, 0.02, 0.005, -0.01};
  const InertiaBudgetOf budget(0.01, input);
  const auto within = [&](const MassProperties& spent) { return budget.Within(spent); };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto draw = [&] {
    const double size = 0.02 * std::pow(10.0, -(unit(rng) + 1) / 2);  // 2e-3 .. 2e-2
    MassProperties spent{0.1 * size * unit(rng), {0, 0, 0}, {}};
    spent.second = size * Sym3{unit(rng), unit(rng), unit(rng), unit(rng), unit(rng), unit(rng)};
    spent.moment = 0.5 * size * DVec3{unit(rng), unit(rng), unit(rng)};
    if (unit(rng) > 0) {
      DVec3 axis{unit(rng), unit(rng), unit(rng)};
      axis = (1.0 / Norm(axis)) * axis;
      spent.second =
          0.01 * spent.second + Turned(input.second, axis, 0.3 * unit(rng)) - input.second;
      spent.moment = 0.01 * spent.moment;
    }
    return spent;
  };
  std::vector<MassProperties> accepted;
  while (accepted.size() < 200) {
    const MassProperties spent = draw();
    if (within(spent)) accepted.push_back(spent);
  }
  for (size_t i = 0; i + 1 < accepted.size(); i += 2) {
    const MassProperties &a = accepted[i], &b = accepted[i + 1];
    for (const double w : {0.5, 0.1, 0.9}) {
      MassProperties mix{
          w * a.measure + (1 - w) * b.measure, w * a.moment + (1 - w) * b.moment, {}};
      mix.second = w * a.second + (1 - w) * b.second;
      EXPECT_TRUE(within(mix)) << "pair " << i << " weight " << w;
    }
  }
}

// A compound collapse (engine/seam_collapse.h) spends for all its copies or none: each change is
// judged at its share times their number, so changes the budget takes one by one may be refused
// together, and then nothing is spent.
TEST(Rules, CompoundCollapsesSpendTheBudgetsTogether) {
  SimplifyOptions o;
  o.max_volume_change = 0.01;  // 1.0 of the input's 100
  const MassProperties input{100.0, {0, 0, 0}, {}};
  const FieldResultants none;
  const RuleSet set = ClosedMeshRules(o, input, none);
  CollapseDelta small, large;
  small.mass.measure = 0.3;
  large.mass.measure = 0.6;
  Reject refused = Reject::kCount;
  // 2 x 0.6 is over 1.0: refused together (alone, 0.6 would pass), nothing spent.
  const CollapseDelta refused_pair[] = {small, large};
  EXPECT_FALSE(set.SpendBudgetsTogether(refused_pair, &refused));
  EXPECT_EQ(refused, Reject::kVolume);
  // Nothing was spent: 0.45 twice (judged 0.9 each) still fits, and is spent (0.9 in all) ...
  CollapseDelta half;
  half.mass.measure = 0.45;
  const CollapseDelta pair[] = {half, half};
  EXPECT_TRUE(set.SpendBudgetsTogether(pair, &refused));
  // ... so that 0.2 more (0.9 + 0.2 > 1.0) no longer does.
  CollapseDelta rest;
  rest.mass.measure = 0.2;
  EXPECT_FALSE(set.SpendBudgets(0, rest, &refused));
}

}  // namespace
}  // namespace femsimp
