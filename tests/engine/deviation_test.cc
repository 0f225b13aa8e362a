// The deviation bound of one collapse (engine/deviation.h) on hand-made fans: what the
// displacement box keeps from adding up, and what it must still add.
#include "engine/deviation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "engine/rule.h"
#include "engine/triangle_distance.h"
#include "tests/support/meshes.h"

namespace femsimp {
namespace {

// A closed fan of six faces: the neighbours on the unit hexagon at z = 0, the centre at height
// h (a tent; 0 is flat).
Ring Tent(float h) { return testing::RegularFan(6, h); }

constexpr double kNoLimit = std::numeric_limits<double>::infinity();

// The largest new bound over the faces that survive collapsing the tent's centre onto
// neighbour 0, every old face having moved as `old`.
Displacement Collapse(const Ring& fan, const Displacement& old) {
  Displacement old_moved[kMaxRing], new_moved[kMaxRing];
  for (int f = 0; f < fan.faces; ++f) old_moved[f] = old;
  int work = 0;
  EXPECT_TRUE(BoundDeviation(fan, 0, -1, old_moved, kNoLimit, new_moved, &work));
  EXPECT_GT(work, 0);
  Displacement worst;
  for (int f = 1; f < fan.faces - 1; ++f)  // faces 0 and 5 hold V - Vd and go
    if (new_moved[f].bound > worst.bound) worst = new_moved[f];
  return worst;
}

constexpr double kEps = 1e-6;

// Flattening a tent of height 0.1 moves the apex 0.1 straight down.
TEST(Deviation, FlatteningATentMovesItsApexDown) {
  const Displacement d = Collapse(Tent(0.1f), Displacement{});
  EXPECT_NEAR(d.bound, 0.1, kEps);
  EXPECT_NEAR(d.lo.z, -0.1, kEps);
  EXPECT_NEAR(d.hi.z, 0.0, kEps);
  EXPECT_NEAR(d.lo.x, 0.0, kEps);
  EXPECT_NEAR(d.hi.x, 0.0, kEps);
}

// Points that had moved up by 0.1 and now move down by 0.1 have moved at most 0.1 in all, not
// 0.2 as adding lengths would say.
TEST(Deviation, StepsInAndOutDoNotAddUp) {
  Displacement up;
  up.bound = 0.1;
  up.hi = {0, 0, 0.1};
  const Displacement d = Collapse(Tent(0.1f), up);
  EXPECT_NEAR(d.bound, 0.1, kEps);
  EXPECT_NEAR(d.lo.z, -0.1, kEps);
  EXPECT_NEAR(d.hi.z, 0.1, kEps);
}

// Steps the same way still add: the guarantee is kept.
TEST(Deviation, StepsTheSameWayAddUp) {
  Displacement down;
  down.bound = 0.1;
  down.lo = {0, 0, -0.1};
  const Displacement d = Collapse(Tent(0.1f), down);
  EXPECT_NEAR(d.bound, 0.2, kEps);
  EXPECT_NEAR(d.lo.z, -0.2, kEps);
}

// Steps across each other add as a right triangle's sides do.
TEST(Deviation, StepsAcrossEachOtherAddInQuadrature) {
  Displacement sideways;
  sideways.bound = 0.1;
  sideways.hi = {0.1, 0, 0};
  const Displacement d = Collapse(Tent(0.1f), sideways);
  EXPECT_NEAR(d.bound, std::sqrt(0.02), kEps);
}

// A box known only loosely (reaching further than the bound) leaves the bound as the length
// sum says, and is cut back to the bound's cube.
TEST(Deviation, TheBoundCapsALooseBox) {
  Displacement loose;
  loose.bound = 0.05;
  loose.lo = {-1, -1, -1};
  loose.hi = {1, 1, 1};
  const Displacement d = Collapse(Tent(0.1f), loose);
  EXPECT_NEAR(d.bound, 0.15, kEps);
  EXPECT_GE(d.lo.x, -0.15 - kEps);
  EXPECT_LE(d.hi.z, 0.15 + kEps);
}

// A limit only refuses early what the full computation would put beyond it: below the largest
// new bound the collapse is refused, at or above it the same boxes come out, whatever the old
// boxes (steps inwards, outwards, sideways, loose) and the tent's height.
TEST(Deviation, ALimitRefusesOnlyWhatTheBoundExceeds) {
  Displacement olds[5];
  olds[1].bound = 0.1;
  olds[1].hi = {0, 0, 0.1};
  olds[2].bound = 0.1;
  olds[2].lo = {0, 0, -0.1};
  olds[3].bound = 0.1;
  olds[3].hi = {0.1, 0, 0};
  olds[4].bound = 0.05;
  olds[4].lo = {-1, -1, -1};
  olds[4].hi = {1, 1, 1};
  int early_refusals = 0;
  for (const float h : {0.0f, 0.01f, 0.1f, 0.4f}) {
    const Ring fan = Tent(h);
    for (const Displacement& old : olds) {
      Displacement old_moved[kMaxRing], full[kMaxRing], limited[kMaxRing];
      for (int f = 0; f < fan.faces; ++f) old_moved[f] = old;
      int full_work = 0;
      ASSERT_TRUE(BoundDeviation(fan, 0, -1, old_moved, kNoLimit, full, &full_work));
      double worst = 0;
      for (int f = 1; f < fan.faces - 1; ++f) worst = std::max(worst, full[f].bound);
      for (const double scale : {0.5, 0.9, 0.999, 1.0, 1.001, 2.0}) {
        const double limit = scale * worst;
        int work = 0;
        const bool within = BoundDeviation(fan, 0, -1, old_moved, limit, limited, &work);
        if (!within) {
          EXPECT_LT(limit, worst) << "h " << h << " old bound " << old.bound;
          EXPECT_LT(work, full_work) << "refused before the overlay";
          ++early_refusals;
          continue;
        }
        for (int f = 1; f < fan.faces - 1; ++f) {
          EXPECT_EQ(limited[f].bound, full[f].bound);
          EXPECT_EQ(limited[f].lo.z, full[f].lo.z);
          EXPECT_EQ(limited[f].hi.x, full[f].hi.x);
        }
      }
    }
  }
  EXPECT_GT(early_refusals, 0) << "the floor refuses some limits below the bound";
}

// The rule stores the box in 16-bit steps of the tolerance, rounded outwards, reads it back for
// the next collapse, and refuses a face beyond the tolerance.
TEST(Deviation, TheRuleKeepsTheBoxAcrossCollapses) {
  RuleSetup setup;
  setup.tolerance = 0.15f;
  const RuleSet set = RuleSet::Build(SimplifyOptions{}, setup);
  const CollapseRule* tolerance = nullptr;
  for (const CollapseRule* r : set.stage(RuleStage::kFidelity))
    if (r->reason() == Reject::kTolerance) tolerance = r;
  ASSERT_NE(tolerance, nullptr);

  const Ring tent = Tent(0.1f);
  FaceAttrQ attrs[kMaxRing] = {};
  for (int f = 0; f < tent.faces; ++f) attrs[f].moved_hi[2] = 16384 * 2 / 3;  // up by 0.1
  attrs[0].error = attrs[1].error = attrs[2].error = attrs[3].error = attrs[4].error =
      attrs[5].error = 0.1f;
  CollapseProposal p;
  p.fan = &tent;
  p.target = 0;
  p.fan_attr = attrs;
  for (int f = 0; f < tent.faces; ++f) p.new_attr[f] = attrs[f];
  ASSERT_EQ(tolerance->Check(RuleStage::kFidelity, p), Verdict::kPass)
      << "up 0.1 then down 0.1 is within 0.15";
  const double unit = 0.15 / 16384;
  double lowest = 0.0;
  for (int f = 1; f < 5; ++f) {
    const FaceAttrQ& a = p.new_attr[f];
    EXPECT_LE(a.error, 0.1f + 1e-5f);
    EXPECT_GE(a.moved_hi[2], attrs[f].moved_hi[2]) << "the old box is kept";
    EXPECT_GE(a.moved_lo[0], -1) << "nothing moved sideways but rounding";
    EXPECT_LE(a.moved_hi[0], 1);
    lowest = std::min(lowest, a.moved_lo[2] * unit);
  }
  EXPECT_LE(lowest, -0.1) << "the apex's step, rounded outwards";

  // The same way twice is 0.2: refused.
  for (int f = 0; f < tent.faces; ++f) {
    attrs[f].moved_hi[2] = 0;
    attrs[f].moved_lo[2] = -16384 * 2 / 3;
    p.new_attr[f] = attrs[f];
  }
  EXPECT_EQ(tolerance->Check(RuleStage::kFidelity, p), Verdict::kReject);
}

// BoundReach (the measured check's part (b) without measuring): on random fans, every sampled
// point of a new face lies within its bound of the old patch (the set its faces are within 0
// of), and within it less the old faces' reach when they are given one; the bound is not far
// above the truth on a gentle fan.
TEST(Deviation, ReachBoundsHoldOnRandomFans) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25), height(-0.3, 0.3);
  int checked = 0, built = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 4 + trial % 6;
    Ring fan = testing::RegularFan(n, static_cast<float>(height(rng)));
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * (i + jitter(rng)) / n;
      const double r = 1.0 + jitter(rng);
      fan.pos[i] = {static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)),
                    static_cast<float>(0.2 * height(rng))};
    }
    const double extra = trial % 2 == 0 ? 0.0 : 0.05;  // a reach the old faces already have
    double old_reach[kMaxRing], new_reach[kMaxRing];
    for (int f = 0; f < n; ++f) old_reach[f] = extra;
    const int target = trial % n;
    if (!BoundReach(fan, target, -1, old_reach, new_reach)) continue;
    ++built;
    const DVec3 v = ToD(fan.center_pos), vd = ToD(fan.pos[target]);
    for (int g = 0; g < n; ++g) {
      if (g == target || (g + 1) % n == target) continue;
      const DVec3 b = ToD(fan.pos[g]), c = ToD(fan.pos[(g + 1) % n]);
      double worst = 0;
      for (int i = 0; i <= 12; ++i)
        for (int j = 0; i + j <= 12; ++j) {
          const DVec3 x = (i / 12.0) * vd + (j / 12.0) * b + ((12 - i - j) / 12.0) * c;
          double d2 = 1e300;
          for (int f = 0; f < n; ++f)
            d2 = std::min(
                d2, SquaredDistanceToTriangle(x, v, ToD(fan.pos[f]), ToD(fan.pos[(f + 1) % n])));
          worst = std::max(worst, std::sqrt(d2));
        }
      EXPECT_LE(worst + extra, new_reach[g] + 1e-9) << "trial " << trial << " face " << g;
      ++checked;
    }
  }
  EXPECT_GT(built, 100);
  EXPECT_GT(checked, 300);
  // A flat fan stays where it is: the bound is the old reach alone.
  const Ring flat = testing::RegularFan(6, 0.0f);
  double old_reach[kMaxRing], new_reach[kMaxRing];
  for (int f = 0; f < 6; ++f) old_reach[f] = 0.01;
  ASSERT_TRUE(BoundReach(flat, 0, -1, old_reach, new_reach));
  for (int g = 1; g < 5; ++g) EXPECT_NEAR(new_reach[g], 0.01, 1e-6);
}

const CollapseRule& ToleranceRule(const RuleSet& set) {
  for (const CollapseRule* r : set.stage(RuleStage::kFidelity))
    if (r->reason() == Reject::kTolerance) return *r;
  ADD_FAILURE() << "no tolerance rule";
  return *set.stage(RuleStage::kFidelity).front();
}

// A proposal on `fan` towards `target`, every face's bound `bound` and box up to `up` in z; with
// `uneven`, every other face has not moved and the rest may have moved anywhere within `bound`
// (the box a cube, in the rule's steps of `unit`).
CollapseProposal Proposal(const Ring& fan, int target, float bound, int16_t up, FaceAttrQ* attrs,
                          bool uneven = false, double unit = 1.0) {
  for (int f = 0; f < fan.faces; ++f) {
    attrs[f] = FaceAttrQ{};
    if (uneven && f % 2 == 0) continue;
    attrs[f].error = bound;
    attrs[f].moved_hi[2] = up;
    if (!uneven) continue;
    const auto steps = static_cast<int16_t>(std::ceil(bound / unit));
    for (int i = 0; i < 3; ++i) {
      attrs[f].moved_lo[i] = static_cast<int16_t>(-steps);
      attrs[f].moved_hi[i] = steps;
    }
  }
  CollapseProposal p;
  p.fan = &fan;
  p.target = target;
  p.fan_attr = attrs;
  for (int f = 0; f < fan.faces; ++f) p.new_attr[f] = attrs[f];
  return p;
}

bool SameAttrs(const CollapseProposal& a, const CollapseProposal& b) {
  for (int f = 0; f < a.fan->faces; ++f) {
    const FaceAttrQ &x = a.new_attr[f], &y = b.new_attr[f];
    if (x.error != y.error) return false;
    for (int i = 0; i < 3; ++i)
      if (x.moved_lo[i] != y.moved_lo[i] || x.moved_hi[i] != y.moved_hi[i]) return false;
  }
  return true;
}

// The screen (RuleStage::kScreen) refuses only directions the fidelity check refuses, and the
// fidelity check after it (which reuses the screen's layout) decides and proposes exactly what
// it does alone.
TEST(Deviation, TheScreenRefusesOnlyWhatTheCheckRefuses) {
  RuleSetup setup;
  setup.tolerance = 0.15f;
  const RuleSet set = RuleSet::Build(SimplifyOptions{}, setup);
  ASSERT_EQ(set.stage(RuleStage::kScreen).size(), 1u);
  const CollapseRule& rule = ToleranceRule(set);
  ASSERT_EQ(set.stage(RuleStage::kScreen).front(), &rule);
  const double unit = 0.15 / 16384;  // the rule's box step
  int screened = 0, passed = 0, refused_later = 0;
  uint64_t serial = 1;
  for (const float h : {0.0f, 0.05f, 0.1f, 0.14f, 0.2f, 0.4f}) {
    const Ring fan = Tent(h);
    for (const float bound : {0.0f, 0.03f, 0.1f, 0.149f}) {
      for (const int16_t up : {int16_t{0}, int16_t{4000}, int16_t{16000}}) {
        for (int target = 0; target < 2 * fan.neighbours(); ++target) {
          // The second round: the floor is the least over the old faces, the bound the most.
          const bool uneven = target >= fan.neighbours();
          const int t = target % fan.neighbours();
          FaceAttrQ attrs[kMaxRing], alone_attrs[kMaxRing];
          CollapseProposal alone = Proposal(fan, t, bound, up, alone_attrs, uneven, unit);
          const Verdict truth = rule.Check(RuleStage::kFidelity, alone);
          CollapseProposal p = Proposal(fan, t, bound, up, attrs, uneven, unit);
          p.fan_serial = serial++;
          if (rule.Check(RuleStage::kScreen, p) == Verdict::kReject) {
            EXPECT_EQ(truth, Verdict::kReject) << "h " << h << " bound " << bound;
            ++screened;
            continue;
          }
          EXPECT_EQ(rule.Check(RuleStage::kFidelity, p), truth);
          if (truth == Verdict::kPass) {
            EXPECT_TRUE(SameAttrs(p, alone));
            ++passed;
          } else {
            ++refused_later;
          }
        }
      }
    }
  }
  EXPECT_GT(screened, 0);
  EXPECT_GT(passed, 0);
  EXPECT_GT(refused_later, 0) << "the overlay refuses what the screen cannot tell";
}

// The rule keeps a candidate's layout per thread, keyed by the proposal's fan serial: a check
// on another fan in between (an SPE software thread's, on the cell back end) is told apart.
TEST(Deviation, TheRuleTellsInterleavedFansApart) {
  RuleSetup setup;
  setup.tolerance = 0.15f;
  const RuleSet set = RuleSet::Build(SimplifyOptions{}, setup);
  const CollapseRule& rule = ToleranceRule(set);
  const Ring low = Tent(0.05f), high = Tent(0.3f);
  FaceAttrQ a_attrs[kMaxRing], b_attrs[kMaxRing], alone_attrs[kMaxRing];
  CollapseProposal a = Proposal(low, 0, 0.0f, 0, a_attrs);
  CollapseProposal b = Proposal(high, 0, 0.0f, 0, b_attrs);
  a.fan_serial = 11;
  b.fan_serial = 12;
  ASSERT_EQ(rule.Check(RuleStage::kScreen, a), Verdict::kPass);
  EXPECT_EQ(rule.Check(RuleStage::kScreen, b), Verdict::kReject) << "0.3 down is beyond 0.15";
  ASSERT_EQ(rule.Check(RuleStage::kFidelity, a), Verdict::kPass);
  CollapseProposal alone = Proposal(low, 0, 0.0f, 0, alone_attrs);
  ASSERT_EQ(rule.Check(RuleStage::kFidelity, alone), Verdict::kPass);
  EXPECT_TRUE(SameAttrs(a, alone));
  // A proposal no kernel made (serial 0) keeps nothing: judged on its own fan right after a's.
  ASSERT_EQ(rule.Check(RuleStage::kScreen, a), Verdict::kPass);
  CollapseProposal c = Proposal(high, 0, 0.0f, 0, b_attrs);
  EXPECT_EQ(rule.Check(RuleStage::kFidelity, c), Verdict::kReject);
}

}  // namespace
}  // namespace femsimp
