// The deterministic schedule (engine/rounds.h): one output for a given input and options,
// whatever the number of threads or SPEs and on either back end, with every rule that keeps
// shared state in play (vertex target, volume and field budgets, the face index).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "engine/mechanics.h"
#include "engine/simplify.h"
#include "tests/support/meshes.h"
#include "tests/support/sanitizers.h"

namespace femsimp {
namespace {

using testing::SimplifyChecked;
using testing::SimplifyRun;

struct Context {
  Backend backend;
  int contexts;  // threads or SPEs
  int spe_threads = 1;
};

SimplifyOptions With(SimplifyOptions o, const Context& c) {
  o.backend = c.backend;
  if (c.backend == Backend::kCell) {
    o.cell.spes = c.contexts;
    o.cell.spe_threads = c.spe_threads;
  } else {
    o.threads = c.contexts;
  }
  return o;
}

void ExpectSameOutput(const SimplifyRun& a, const SimplifyRun& b, const std::string& what) {
  EXPECT_EQ(a.output.positions, b.output.positions) << what;
  EXPECT_EQ(a.output.triangles, b.output.triangles) << what;
  EXPECT_EQ(a.output.face_groups, b.output.face_groups) << what;
  ASSERT_EQ(a.output.face_fields.size(), b.output.face_fields.size()) << what;
  for (size_t i = 0; i < a.output.face_fields.size(); ++i)
    EXPECT_EQ(a.output.face_fields[i].values, b.output.face_fields[i].values) << what;
  EXPECT_EQ(a.result.passes.size(), b.result.passes.size()) << what;
}

class Deterministic : public ::testing::TestWithParam<std::tuple<std::string, int>> {};

// Option sets that exercise each piece of shared state.
SimplifyOptions OptionSet(int which) {
  SimplifyOptions o;  // the fe preset: tolerance, volume budget, self-intersection index
  switch (which) {
    case 1:  // a vertex target, the quadric cost
      o.cost = CostKind::kQuadric;
      o.ratio = 0.08;
      break;
    case 2:  // a tight volume budget and a centroid budget: refusals by the ledger
      o.max_volume_change = 0.001;
      o.max_centroid_shift = 0.0005;
      break;
    case 3:  // full-edge collapses: vertices move, locks and boxes reach V's two-ring
      o.placement = Placement::kOptimal;
      o.max_inertia_change = 0.005;
      break;
    default:
      break;
  }
  return o;
}

TEST_P(Deterministic, SameOutputForAnyContextCountAndBackEnd) {
  const auto& [name, which] = GetParam();
  RawMesh input = testing::LoadTestMesh(name);
  // And the field budget (rotor_small's thin blades keep almost every vertex with fields on).
  if (which == 2 && name == "fandisk.off") input = testing::WithGroupsAndFields(input);
  const SimplifyOptions options = OptionSet(which);
  ASSERT_EQ(options.schedule, Schedule::kDeterministic);
  const SimplifyRun reference = SimplifyChecked(input, With(options, {Backend::kNative, 1}));
  ASSERT_LT(reference.output.num_vertices(), input.num_vertices() * 9 / 10);
  const std::vector<Context> others = {{Backend::kNative, 1}, {Backend::kNative, 2},
                                       {Backend::kNative, 4}, {Backend::kCell, 1},
                                       {Backend::kCell, 4},   {Backend::kCell, 3, 2}};
  for (const Context& c : others) {
    const std::string what = (c.backend == Backend::kCell ? "cell, SPEs " : "native, threads ") +
                             std::to_string(c.contexts) + " x" + std::to_string(c.spe_threads);
    ExpectSameOutput(reference, SimplifyChecked(input, With(options, c)), what);
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, Deterministic,
                         ::testing::Combine(::testing::Values("fandisk.off", "rotor_small.off"),
                                            ::testing::Values(0, 1, 2, 3)));

// A round keeps a loser's box from the round that read it while nothing it was made of changed
// (engine/rounds.h): the self-check reads each kept box again and fails the run where the two
// differ. Runs `o` with and without it: the same output and the same boxes kept; returns the
// plain run's boxes kept, candidates tried and rounds.
struct KeptBoxes {
  uint64_t kept = 0, tried = 0, rounds = 0;
};
KeptBoxes ExpectOnlyFreshBoxesKept(const RawMesh& input, const SimplifyOptions& o,
                                   const std::string& what) {
  SimplifyControl check;
  check.check_kept_boxes = true;
  const SimplifyRun checked = testing::SimplifyCheckedWith(input, o, check);
  const SimplifyRun plain = SimplifyChecked(input, o);
  ExpectSameOutput(checked, plain, what);
  KeptBoxes k;
  for (const PassStats& p : plain.result.passes) {
    k.kept += p.boxes_kept;
    k.tried += p.tried;
    k.rounds += p.rounds;
  }
  uint64_t kept_checked = 0;
  for (const PassStats& p : checked.result.passes) kept_checked += p.boxes_kept;
  EXPECT_EQ(kept_checked, k.kept) << what;
  return k;
}

// One thread has nothing for ThreadSanitizer to find, and takes half of this test's time there.
std::vector<int> ThreadCounts() {
  return testing::kUnderThreadSanitizer ? std::vector<int>{2} : std::vector<int>{1, 2};
}

// With full-edge collapses (boxes over V's two-ring), and with half-edge collapses (V's
// one-ring) at a tolerance that refuses most winners: the boxes kept are many.
TEST(Deterministic, RoundsKeepOnlyBoxesAFreshReadGives) {
  for (const char* name : {"fandisk.off", "rotor_small.off"}) {
    const RawMesh input = testing::LoadTestMesh(name);
    for (const bool measured : {false, true}) {
      if (measured && std::string(name) == "fandisk.off") continue;  // minutes under TSan
      SimplifyOptions o = OptionSet(3);
      if (measured) {
        o.deviation_check = DeviationCheck::kMeasured;
        o.feature_angle_deg = 180;
        o.tolerance_relative = 0.01;
        o.max_inertia_change = 0;
      }
      for (const int threads : ThreadCounts()) {
        o.threads = threads;
        const std::string what = std::string(name) + (measured ? ", measured" : ", mapped") +
                                 ", threads " + std::to_string(threads);
        const KeptBoxes k = ExpectOnlyFreshBoxesKept(input, o, what);
        // Most candidates lose a few rounds before they run: more boxes kept than tried.
        EXPECT_GT(k.kept, k.tried) << what << ", rounds " << k.rounds;
      }
    }
    SimplifyOptions o;  // bound only, half-edge collapses
    o.max_volume_change = 0;
    o.min_angle_deg = 0;
    o.max_normal_deviation_deg = 180;
    o.tolerance_relative = 0.001;
    for (const int threads : ThreadCounts()) {
      o.threads = threads;
      const std::string what =
          std::string(name) + ", half-edge, threads " + std::to_string(threads);
      const KeptBoxes k = ExpectOnlyFreshBoxesKept(input, o, what);
      EXPECT_GT(k.kept, k.tried / 2) << what << ", rounds " << k.rounds;
    }
  }
}

TEST(Deterministic, RoundsStopExactlyAtTheTarget) {
  SimplifyOptions o;
  o.target_vertices = 777;
  o.tolerance_relative = 0.0;
  o.threads = 2;
  const SimplifyRun run = SimplifyChecked(testing::LoadTestMesh("fandisk.off"), o);
  EXPECT_EQ(run.result.output_vertices, 777u);
  EXPECT_EQ(run.result.stop_reason, StopReason::kTargetReached);
  uint64_t rounds = 0;
  for (const PassStats& p : run.result.passes) rounds += p.rounds;
  EXPECT_GT(rounds, run.result.passes.size());  // several rounds a pass
}

TEST(Deterministic, FreeScheduleRunsOnePhaseAPass) {
  SimplifyOptions o = PresetOptions(Preset::kPaper);
  ASSERT_EQ(o.schedule, Schedule::kFree);
  const SimplifyRun run = SimplifyChecked(testing::LoadTestMesh("fandisk.off"), o);
  for (const PassStats& p : run.result.passes) EXPECT_EQ(p.rounds, 0u);
}

// The ledger in a round judges each delta scaled by the winners against the round's starting
// totals, and sums the accepted ones in vertex order afterwards.
TEST(LedgerRounds, JudgesSharesAndSumsInVertexOrder) {
  MassProperties input{1.0, {0, 0, 0}, {}};
  FieldResultants fields;
  MechanicsLedger ledger(input, fields);
  CollapseDelta d;
  d.mass.measure = 0.004;
  const auto within = [](double limit) {
    return [limit](const LedgerView& t) { return std::fabs(t.spent.measure) <= limit; };
  };
  ledger.BeginRound(3);
  EXPECT_EQ(ledger.round_scale(), 3.0);
  const CollapseDelta judged = Scaled(d, ledger.round_scale());
  EXPECT_DOUBLE_EQ(judged.mass.measure, 0.012);
  // 0.012 (its share of the round) is over 0.01: refused although 0.004 alone would fit.
  EXPECT_FALSE(ledger.TryCommit(7, d, judged, within(0.01)));
  EXPECT_TRUE(ledger.TryCommit(9, d, judged, within(0.02)));
  // Still the round's starting totals: the accepted delta is not spent yet.
  EXPECT_TRUE(ledger.TryCommit(2, d, judged, within(0.012)));
  ledger.EndRound();
  EXPECT_EQ(ledger.round_scale(), 1.0);
  // Outside a round the delta itself is judged against the running totals (0.008 spent).
  EXPECT_FALSE(ledger.TryCommit(1, d, d, within(0.0115)));
  EXPECT_TRUE(ledger.TryCommit(1, d, d, within(0.0125)));
}

}  // namespace
}  // namespace femsimp
