// Service pieces without a server: argument parsing, wire conversions, chunking, stream
// validation, the job queue, the stats JSON.
#include <array>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "client/args.h"
#include "client/report.h"
#include "gtest/gtest.h"
#include "proto/wire.h"
#include "server/job_queue.h"
#include "server/job_registry.h"
#include "server/log.h"
#include "server/memory_budget.h"
#include "server/request_reader.h"
#include "server/result_stream.h"
#include "tests/service/test_util.h"

namespace femsimp {
namespace {

using cli::ParseCommandLine;

absl::StatusOr<cli::Command> Parse(std::vector<std::string> args) {
  args.insert(args.begin(), "femsimp");
  return ParseCommandLine(args);
}

TEST(Args, SimplifyWithEveryOption) {
  auto cmd = Parse({"simplify",
                    "in.off",
                    "out.ply",
                    "--ratio",
                    "0.25",
                    "--threads=3",
                    "--max-normal-deviation",
                    "30",
                    "--min-angle",
                    "5",
                    "--candidate-fraction",
                    "0.5",
                    "--max-passes",
                    "7",
                    "--topology-only",
                    "--backend",
                    "cell",
                    "--spes",
                    "4",
                    "--ls-cache-kib",
                    "64",
                    "--spe-threads",
                    "2",
                    "--stats-json",
                    "s.json"});
  ASSERT_TRUE(cmd.ok()) << cmd.status();
  const cli::SimplifyArgs& a = cmd->simplify;
  EXPECT_EQ(a.input, "in.off");
  EXPECT_EQ(a.output, "out.ply");
  EXPECT_DOUBLE_EQ(a.options.ratio, 0.25);
  EXPECT_EQ(a.options.threads, 3);
  EXPECT_DOUBLE_EQ(a.options.max_normal_deviation_deg, 30);
  EXPECT_DOUBLE_EQ(a.options.min_angle_deg, 5);
  EXPECT_DOUBLE_EQ(a.options.candidate_fraction, 0.5);
  EXPECT_EQ(a.options.max_passes, 7);
  EXPECT_TRUE(a.options.topology_only);
  EXPECT_EQ(a.options.backend, Backend::kCell);
  EXPECT_EQ(a.options.cell.spes, 4);
  EXPECT_EQ(a.options.cell.ls_cache_kib, 64);
  EXPECT_EQ(a.options.cell.spe_threads, 2);
  EXPECT_EQ(a.stats_json, "s.json");
  EXPECT_TRUE(a.server.empty());
}

TEST(Args, FidelityOptions) {
  auto cmd =
      Parse({"simplify", "in.ply", "out.ply", "--cost", "quadric", "--tolerance", "0.02",
             "--tolerance-relative", "0.1%", "--feature-angle=45", "--max-volume-change", "0.5%",
             "--max-centroid-shift", "0.001", "--max-field-change", "2%", "--drop-face-data"});
  ASSERT_TRUE(cmd.ok()) << cmd.status();
  const SimplifyOptions& o = cmd->simplify.options;
  EXPECT_EQ(o.cost, CostKind::kQuadric);
  EXPECT_DOUBLE_EQ(o.tolerance, 0.02);
  EXPECT_DOUBLE_EQ(o.tolerance_relative, 0.001);
  EXPECT_DOUBLE_EQ(o.feature_angle_deg, 45);
  EXPECT_DOUBLE_EQ(o.max_volume_change, 0.005);
  EXPECT_DOUBLE_EQ(o.max_centroid_shift, 0.001);
  EXPECT_DOUBLE_EQ(o.max_field_change, 0.02);
  EXPECT_TRUE(cmd->simplify.drop_face_data);
  // Unset: the engine's defaults.
  auto plain = Parse({"simplify", "in.ply", "out.ply"});
  ASSERT_TRUE(plain.ok()) << plain.status();
  const SimplifyOptions engine;
  EXPECT_EQ(plain->simplify.options.cost, engine.cost);
  EXPECT_EQ(plain->simplify.options.tolerance, engine.tolerance);
  EXPECT_EQ(plain->simplify.options.feature_angle_deg, engine.feature_angle_deg);
  EXPECT_EQ(plain->simplify.options.max_field_change, engine.max_field_change);
  EXPECT_FALSE(plain->simplify.drop_face_data);
  auto gaussian = Parse({"simplify", "a", "b", "--cost", "gaussian_curvature"});
  ASSERT_TRUE(gaussian.ok()) << gaussian.status();
  EXPECT_EQ(gaussian->simplify.options.cost, CostKind::kGaussianCurvature);
}

TEST(Args, Help) {
  auto top = Parse({"--help"});
  ASSERT_TRUE(top.ok());
  EXPECT_EQ(top->kind, cli::Command::kHelp);
  auto sub = Parse({"simplify", "--help"});
  ASSERT_TRUE(sub.ok());
  for (const char* flag : {"--ratio",
                           "--target-vertices",
                           "--threads",
                           "--max-normal-deviation",
                           "--min-angle",
                           "--candidate-fraction",
                           "--max-passes",
                           "--topology-only",
                           "--backend",
                           "--spes",
                           "--ls-cache-kib",
                           "--spe-threads",
                           "--stats-json",
                           "--server",
                           "--deadline",
                           "Exit codes",
                           "--cost gaussian|quadric",
                           "--tolerance D",
                           "--tolerance-relative F",
                           "--feature-angle D",
                           "--max-volume-change F",
                           "--max-centroid-shift F",
                           "--max-field-change F",
                           "(default 0.01)",
                           "(default 30)",
                           "--drop-face-data"})
    EXPECT_NE(sub->help_text.find(flag), std::string::npos) << flag;
}

TEST(Args, Errors) {
  struct Case {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"simplify", "a", "b", "--bogus"}, "unknown option '--bogus'"},
      {{"simplify", "a", "b", "--ratio"}, "--ratio needs a value"},
      {{"simplify", "a", "b", "--ratio", "abc"}, "not a finite number"},
      {{"simplify", "a", "b", "--ratio", "1.5"}, "ratio = 1.5 is out of range"},
      {{"simplify", "a", "b", "--threads", "0"}, "--threads = 0 is out of range"},
      {{"simplify", "a", "b", "--min-angle", "70"},
       "--min-angle = 70 is out of range: must be in [0, 60) degrees"},
      {{"simplify", "a", "b", "--ratio", "0.5", "--target-vertices", "10"}, "not both"},
      {{"simplify", "a", "b", "--spes", "2"}, "needs --backend cell"},
      {{"simplify", "a", "b", "--backend", "gpu"}, "not one of native, cell"},
      {{"simplify", "a", "b", "--cost", "cheap"},
       "--cost: 'cheap' is not one of gaussian, quadric"},
      {{"simplify", "a", "b", "--tolerance", "-1"}, "tolerance = -1 is out of range"},
      {{"simplify", "a", "b", "--tolerance", "fine"}, "--tolerance: 'fine' is not a finite number"},
      {{"simplify", "a", "b", "--tolerance-relative", "x%"},
       "--tolerance-relative: 'x%' is not a finite number or percentage"},
      {{"simplify", "a", "b", "--tolerance-relative", "150%"},
       "--tolerance-relative = 1.5 is out of range"},
      {{"simplify", "a", "b", "--feature-angle", "0"}, "--feature-angle = 0 is out of range"},
      {{"simplify", "a", "b", "--max-volume-change", "2"},
       "--max-volume-change = 2 is out of range"},
      {{"simplify", "a", "b", "--max-centroid-shift", "-1%"},
       "--max-centroid-shift = -0.01 is out of range"},
      {{"simplify", "a", "b", "--max-field-change", "0"}, "--max-field-change = 0 is out of range"},
      {{"simplify", "a", "b", "--drop-face-data=yes"}, "--drop-face-data takes no value"},
      {{"simplify", "a"}, "exactly two files"},
      {{"simplify", "a", "b", "--deadline", "3"}, "need --server"},
      {{"simplify", "a", "b", "--server", "nohost"}, "HOST:PORT"},
      {{"frobnicate"}, "unknown command"},
      {{}, "missing command"},
  };
  for (const Case& c : cases) {
    auto r = Parse(c.args);
    ASSERT_FALSE(r.ok()) << c.message;
    EXPECT_NE(r.status().message().find(c.message), std::string::npos) << r.status();
  }
}

TEST(Wire, OptionsRoundTrip) {
  SimplifyOptions o;
  o.target_vertices = 1234;
  o.threads = 3;
  o.min_angle_deg = 7;
  o.backend = Backend::kCell;
  o.cell.spes = 6;
  v1::EngineOptions m;
  wire::ToProto(o, true, &m);
  auto back = wire::FromProto(m, 1, 64);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->target_vertices, 1234u);
  EXPECT_EQ(back->threads, 3);
  EXPECT_DOUBLE_EQ(back->min_angle_deg, 7);
  EXPECT_EQ(back->backend, Backend::kCell);
  EXPECT_EQ(back->cell.spes, 6);
  // Threads are capped by the server; 0 takes its default.
  m.set_threads(100);
  EXPECT_EQ(wire::FromProto(m, 2, 8)->threads, 8);
  m.set_threads(0);
  EXPECT_EQ(wire::FromProto(m, 2, 8)->threads, 2);
  m.set_min_angle_deg(75);
  EXPECT_FALSE(wire::FromProto(m, 2, 8).ok());
}

TEST(Wire, FidelityOptionsRoundTripAndDefaults) {
  // Unset fields take the engine's defaults.
  auto defaults = wire::FromProto(v1::EngineOptions(), 1, 8);
  ASSERT_TRUE(defaults.ok()) << defaults.status();
  const SimplifyOptions engine;
  EXPECT_EQ(defaults->cost, engine.cost);
  EXPECT_EQ(defaults->tolerance, engine.tolerance);
  EXPECT_EQ(defaults->tolerance_relative, engine.tolerance_relative);
  EXPECT_EQ(defaults->feature_angle_deg, engine.feature_angle_deg);
  EXPECT_EQ(defaults->max_volume_change, engine.max_volume_change);
  EXPECT_EQ(defaults->max_centroid_shift, engine.max_centroid_shift);
  EXPECT_EQ(defaults->max_field_change, engine.max_field_change);

  SimplifyOptions o;
  o.cost = CostKind::kQuadric;
  o.tolerance = 0.25;
  o.tolerance_relative = 0.001;
  o.feature_angle_deg = 45;
  o.max_volume_change = 0.02;
  o.max_centroid_shift = 0.003;
  o.max_field_change = 0.05;
  v1::EngineOptions m;
  wire::ToProto(o, false, &m);
  EXPECT_EQ(m.cost(), v1::COST_KIND_QUADRIC);
  auto back = wire::FromProto(m, 1, 8);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->cost, CostKind::kQuadric);
  EXPECT_EQ(back->tolerance, 0.25);
  EXPECT_EQ(back->tolerance_relative, 0.001);
  EXPECT_EQ(back->feature_angle_deg, 45);
  EXPECT_EQ(back->max_volume_change, 0.02);
  EXPECT_EQ(back->max_centroid_shift, 0.003);
  EXPECT_EQ(back->max_field_change, 0.05);

  // Out of range, and values an older or newer peer might send.
  struct Case {
    std::function<void(v1::EngineOptions*)> set;
    std::string message;
  } cases[] = {
      {[](auto* e) { e->set_cost(static_cast<v1::CostKind>(7)); }, "cost = 7 is not a known"},
      {[](auto* e) { e->set_tolerance(-1); }, "tolerance = -1 is out of range"},
      {[](auto* e) { e->set_tolerance_relative(2); }, "tolerance_relative = 2 is out of range"},
      {[](auto* e) { e->set_feature_angle_deg(0); }, "feature_angle_deg = 0 is out of range"},
      {[](auto* e) { e->set_max_volume_change(1.5); }, "max_volume_change = 1.5"},
      {[](auto* e) { e->set_max_centroid_shift(-0.1); }, "max_centroid_shift = -0.1"},
      // Presence matters: an explicit 0 is not "the default 0.01".
      {[](auto* e) { e->set_max_field_change(0); }, "max_field_change = 0 is out of range"},
  };
  for (const Case& c : cases) {
    v1::EngineOptions e;
    c.set(&e);
    auto r = wire::FromProto(e, 1, 8);
    ASSERT_FALSE(r.ok()) << c.message;
    EXPECT_NE(r.status().message().find(c.message), std::string::npos) << r.status();
  }
}

TEST(Wire, FidelityFiguresRoundTrip) {
  SimplifyResult r;
  r.feature_edges = 321;
  r.corner_vertices = 12;
  r.tolerance_abs = 0.5;
  r.deviation_bound = 0.375;
  r.volume_change = -0.0125;
  r.centroid_shift = 1e-4;
  r.max_field_change = 0.008;
  r.input_mass.solid = true;
  r.input_mass.measure = 2.5;
  r.input_mass.centroid = {1, -2, 3};
  r.input_mass.area = 4.5;
  r.output_mass.principal_moments[2] = 7.25;
  r.output_mass.principal_axes[1] = {0, 0, -1};
  r.inertia_change = 0.004;
  r.wall_limited_share = 0.375;
  r.thinnest_wall = 0.0625;
  r.output_crossings = {
      .pairs = 8, .face_a = 12, .face_b = 57, .at = {1.5, -2.25, 3}, .overlaps = {}, .folds = {}};
  r.output_crossings.overlaps = {
      .pairs = 5, .face_a = 7, .face_b = 70, .at = {1, 0, -1}, .area = 2.5};
  r.output_crossings.folds = {.pairs = 3, .face_a = 10, .face_b = 11, .at = {0.5, 0.5, 1}};
  r.coordinates = {.magnitude = 3e6, .spacing = 0.25, .diagonal = 53.5};
  r.parts = {{.input = 8000, .output = 7990.5}, {.input = 1000, .output = 1001.25}};
  v1::Result m;
  wire::FidelityToProto(r, &m);
  SimplifyResult back;
  wire::FidelityFromProto(m, &back);
  EXPECT_EQ(back.feature_edges, 321u);
  EXPECT_EQ(back.corner_vertices, 12u);
  EXPECT_EQ(back.tolerance_abs, 0.5);
  EXPECT_EQ(back.deviation_bound, 0.375);
  EXPECT_EQ(back.volume_change, -0.0125);
  EXPECT_EQ(back.centroid_shift, 1e-4);
  EXPECT_EQ(back.max_field_change, 0.008);
  EXPECT_TRUE(back.input_mass.solid);
  EXPECT_EQ(back.input_mass.measure, 2.5);
  EXPECT_EQ(back.input_mass.centroid.y, -2);
  EXPECT_EQ(back.input_mass.area, 4.5);
  EXPECT_FALSE(back.output_mass.solid);
  EXPECT_EQ(back.output_mass.principal_moments[2], 7.25);
  EXPECT_EQ(back.output_mass.principal_axes[1].z, -1);
  EXPECT_EQ(back.output_mass.principal_axes[0].x, 1);
  EXPECT_EQ(back.inertia_change, 0.004);
  EXPECT_EQ(back.wall_limited_share, 0.375);
  EXPECT_EQ(back.thinnest_wall, 0.0625);
  EXPECT_EQ(back.output_crossings.pairs, 8u);
  EXPECT_EQ(back.output_crossings.face_a, 12u);
  EXPECT_EQ(back.output_crossings.face_b, 57u);
  EXPECT_EQ(back.output_crossings.at, (std::array<double, 3>{1.5, -2.25, 3}));
  EXPECT_EQ(back.output_crossings.overlaps.pairs, 5u);
  EXPECT_EQ(back.output_crossings.overlaps.face_a, 7u);
  EXPECT_EQ(back.output_crossings.overlaps.face_b, 70u);
  EXPECT_EQ(back.output_crossings.overlaps.area, 2.5);
  EXPECT_EQ(back.output_crossings.overlaps.at, (std::array<double, 3>{1, 0, -1}));
  EXPECT_EQ(back.output_crossings.folds.pairs, 3u);
  EXPECT_EQ(back.output_crossings.folds.face_a, 10u);
  EXPECT_EQ(back.output_crossings.folds.face_b, 11u);
  EXPECT_EQ(back.output_crossings.folds.at, (std::array<double, 3>{0.5, 0.5, 1}));
  EXPECT_EQ(back.coordinates.magnitude, 3e6);
  EXPECT_EQ(back.coordinates.spacing, 0.25);
  EXPECT_EQ(back.coordinates.diagonal, 53.5);
  ASSERT_EQ(back.parts.size(), 2u);
  EXPECT_EQ(back.parts[0].output, 7990.5);
  EXPECT_EQ(back.parts[1].input, 1000);
  EXPECT_EQ(back.parts[1].output, 1001.25);
}

// A client's label, or a file name in a message, must not forge a log line or reach the
// operator's terminal as an escape sequence.
TEST(Log, ControlCharactersAreEscaped) {
  EXPECT_EQ(server::EscapedForLog("job 1 label=ok"), "job 1 label=ok");
  EXPECT_EQ(server::EscapedForLog("a\n2026-01-01T00:00:00Z job 9: forged"),
            "a\\x0a2026-01-01T00:00:00Z job 9: forged");
  EXPECT_EQ(server::EscapedForLog(std::string("\x1b[2J\r\x7f\0x", 8)), "\\x1b[2J\\x0d\\x7f\\x00x");
  EXPECT_EQ(server::EscapedForLog("Grüße"), "Grüße");  // UTF-8 stays readable
}

TEST(JobIds, AreUnguessable128BitHex) {
  server::JobRegistry registry(4);
  std::set<std::string> seen;
  for (int i = 0; i < 1000; ++i) {
    const std::string id = registry.NewId();
    ASSERT_EQ(id.size(), 32u) << id;
    EXPECT_EQ(id.find_first_not_of("0123456789abcdef"), std::string::npos) << id;
    EXPECT_TRUE(seen.insert(id).second) << id;
  }
  // No counter shows through: consecutive ids share no long prefix.
  const std::string a = registry.NewId(), b = registry.NewId();
  EXPECT_NE(a.substr(0, 8), b.substr(0, 8));
}

// An assembly's summary says how many seam points went; a part without seams says nothing.
TEST(Report, SummaryCountsSeamPoints) {
  cli::RunReport r;
  r.passes.resize(2);
  EXPECT_EQ(cli::Summary(r).find("seams:"), std::string::npos);
  r.passes[0].seam_points_removed = 5;
  r.passes[1].seam_points_removed = 2;
  EXPECT_NE(cli::Summary(r).find("seams:    7 seam points slid along their seams"),
            std::string::npos)
      << cli::Summary(r);
}

// An assembly's parts: each one's volume in and out, the first four listed and then the one
// that changed most; --stats-json lists them all.
TEST(Report, SummaryGivesEachPartsVolume) {
  cli::RunReport r;
  EXPECT_EQ(cli::Summary(r).find("parts:"), std::string::npos);
  r.fidelity.parts = {{.input = 8000, .output = 8000}, {.input = 4000, .output = 3990}};
  EXPECT_NE(cli::Summary(r).find("parts:    2 solids of an assembly, volume each: part 1 8000 "
                                 "-> 8000 (+0.0000%), part 2 4000 -> 3990 (-0.2500%)\n"),
            std::string::npos)
      << cli::Summary(r);
  for (int k = 0; k < 3; ++k) r.fidelity.parts.push_back({.input = 100, .output = 100});
  r.fidelity.parts.push_back({.input = 100, .output = 100.4});
  EXPECT_NE(cli::Summary(r).find(", part 4 100 -> 100 (+0.0000%), 2 more; the most changed: part "
                                 "6 100 -> 100.4 (+0.4000%)\n"),
            std::string::npos)
      << cli::Summary(r);
  // The wall rule casts its rays into closed parts only; the summary must not say it found
  // no thin wall where it did not look.
  r.fidelity.input_mass = {.solid = true, .measure = 12400, .area = 2000};
  r.fidelity.tolerance_abs = 0.5;
  r.options.max_wall_share = 0.2;
  EXPECT_NE(cli::Summary(r).find("--max-wall-share holds closed parts only: not applied to an "
                                 "assembly"),
            std::string::npos)
      << cli::Summary(r);
  const std::string json = cli::ReportJson(r);
  EXPECT_NE(json.find("\"parts\": [{\"input_volume\": 8000, \"output_volume\": 8000}, "
                      "{\"input_volume\": 4000, \"output_volume\": 3990}"),
            std::string::npos)
      << json;
}

// With placement the summary counts the full-edge collapses, and with the measured check (the
// only one that moves lines) how many of them merged two vertices of one feature line.
TEST(Report, SummaryCountsVerticesPlacedOnLines) {
  cli::RunReport r;
  r.passes.resize(2);
  r.passes[0].placed = 10;
  r.passes[0].placed_on_lines = 3;
  r.passes[1].placed = 2;
  EXPECT_EQ(cli::Summary(r).find("placement:"), std::string::npos);
  r.options.placement = Placement::kOptimal;
  std::string s = cli::Summary(r);
  EXPECT_NE(s.find("placement: 12 full-edge collapses (vertices merged where a mass budget "
                   "refused the half-edge collapse)\n"),
            std::string::npos)
      << s;
  r.options.deviation_check = DeviationCheck::kMeasured;
  s = cli::Summary(r);
  EXPECT_NE(s.find("or the tolerance refused the half-edge collapse; 3 of them on feature lines)"),
            std::string::npos)
      << s;
}

// A solid's summary gives its mean thickness against the tolerance, and warns where the
// tolerance reaches half of it; an open surface, or a run without a tolerance, says nothing.
TEST(Report, SummaryWarnsWhereTheToleranceReachesHalfTheWall) {
  cli::RunReport r;
  r.fidelity.input_mass.solid = true;
  r.fidelity.input_mass.measure = 100.0;  // 2V/A = 2
  r.fidelity.input_mass.area = 100.0;
  r.fidelity.tolerance_abs = 0.5;
  std::string s = cli::Summary(r);
  EXPECT_NE(s.find("walls:    mean thickness 2V/A 2; the tolerance is 25% of it"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.find("warning:"), std::string::npos) << s;
  r.fidelity.tolerance_abs = 1.0;
  s = cli::Summary(r);
  EXPECT_NE(s.find("warning:  the tolerance is 50% of the mean wall thickness"), std::string::npos)
      << s;
  // With the wall rule on, the line says where it lowered the tolerance instead of warning.
  r.fidelity.thinnest_wall = 0.25;
  r.fidelity.wall_limited_share = 0.125;
  s = cli::Summary(r);
  EXPECT_NE(s.find("walls:    mean thickness 2V/A 2; the tolerance is 50% of it; the wall rule "
                   "lowered it on 12.5% of the surface (thinnest wall 0.25)"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.find("warning:"), std::string::npos) << s;
  // On, but no wall within the rays' reach (tolerance / share): it says so, and does not warn.
  r.fidelity.thinnest_wall = 0.0;
  r.fidelity.wall_limited_share = 0.0;
  r.options.max_wall_share = 0.2;
  s = cli::Summary(r);
  EXPECT_NE(s.find("the tolerance is 50% of it; no wall thinner than 5 (the tolerance over "
                   "--max-wall-share): the wall rule lowered it nowhere"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.find("warning:"), std::string::npos) << s;
  r.options.max_wall_share = 0.0;
  r.fidelity.tolerance_abs = 0.0;
  EXPECT_EQ(cli::Summary(r).find("walls:"), std::string::npos);
  r.fidelity.tolerance_abs = 1.0;
  r.fidelity.input_mass.solid = false;
  EXPECT_EQ(cli::Summary(r).find("walls:"), std::string::npos);
}

// An output that intersects itself gets a warning naming a pair: the mesher would refuse it.
TEST(Report, SummaryWarnsWhereTheOutputIntersectsItself) {
  cli::RunReport r;
  EXPECT_EQ(cli::Summary(r).find("intersects itself"), std::string::npos);
  r.fidelity.output_crossings = {
      .pairs = 8, .face_a = 12, .face_b = 57, .at = {1.5, -2, 3}, .overlaps = {}, .folds = {}};
  std::string s = cli::Summary(r);
  EXPECT_NE(s.find("warning:  OUT intersects itself: 8 face pairs cross (the first: faces 12 and "
                   "57, at (1.5, "
                   "-2, 3)); the input's own crossings, kept (the simplification makes none); a "
                   "mesher such as tetgen refuses it"),
            std::string::npos)
      << s;
  r.options.allow_self_intersections = true;
  r.fidelity.output_crossings.pairs = 1;
  s = cli::Summary(r);
  EXPECT_NE(s.find("1 face pair cross (the first: faces 12 and 57"), std::string::npos) << s;
  EXPECT_NE(s.find("--allow-self-intersections let the run make crossings"), std::string::npos)
      << s;
  EXPECT_NE(cli::ReportJson(r).find("\"output_crossings\": {\"pairs\": 1, \"faces\": [12, 57], "
                                    "\"at\": [1.5, -2, 3], \"overlaps\": {\"pairs\": 0}, "
                                    "\"folds\": {\"pairs\": 0}, \"cut_short\": false}"),
            std::string::npos);
}

// Bodies exported apart that touch leave faces overlapping in their plane: a warning of its own,
// with the contact's area, and the figures in --stats-json.
TEST(Report, SummaryWarnsWhereTheOutputHasOverlappingFaces) {
  cli::RunReport r;
  r.fidelity.output_crossings.overlaps = {
      .pairs = 3, .face_a = 4, .face_b = 9, .at = {1, 2, 3}, .area = 0.75};
  const std::string s = cli::Summary(r);
  EXPECT_NE(s.find("warning:  OUT has overlapping faces: 3 face pairs overlap in their plane, over "
                   "an area of 0.75 (the first: faces 4 and 9, at (1, 2, 3)): bodies exported "
                   "apart that touch, each with its own triangulation of the contact; kept from "
                   "the input (the simplification makes none); tetgen and most FE meshers refuse "
                   "overlapping faces"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.find("intersects itself"), std::string::npos) << s;
  EXPECT_NE(cli::ReportJson(r).find("\"output_crossings\": {\"pairs\": 0, \"overlaps\": "
                                    "{\"pairs\": 3, \"area\": 0.75, \"faces\": [4, 9], \"at\": "
                                    "[1, 2, 3]}, \"folds\": {\"pairs\": 0}, \"cut_short\": false}"),
            std::string::npos);
}

// A fold repair could not undo (facets in different face groups) stays in the output: a warning
// naming the first pair, the figures in --stats-json, and the repair summary lists what it left
// though it changed nothing.
TEST(Report, SummaryWarnsWhereTheOutputHasFoldedFaces) {
  cli::RunReport r;
  r.fidelity.output_crossings.folds = {.pairs = 3, .face_a = 10, .face_b = 11, .at = {0.5, 0.5, 1}};
  const std::string s = cli::Summary(r);
  EXPECT_NE(s.find("warning:  OUT has folded faces: 3 face pairs lie on each other in their "
                   "plane, one of each turned over (the first: faces 10 and 11, along their "
                   "common edge at (0.5, 0.5, 1)); kept from the input, where no flip of their "
                   "edge unfolds them (the repair report's fold_left says why); tetgen and most "
                   "FE meshers refuse faces lying on each other"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.find("intersects itself"), std::string::npos) << s;
  EXPECT_EQ(s.find("overlapping faces"), std::string::npos) << s;
  EXPECT_NE(cli::ReportJson(r).find("\"output_crossings\": {\"pairs\": 0, \"overlaps\": "
                                    "{\"pairs\": 0}, \"folds\": {\"pairs\": 3, \"faces\": "
                                    "[10, 11], \"at\": [0.5, 0.5, 1]}, \"cut_short\": false}"),
            std::string::npos);
  RepairReport repair;
  EXPECT_EQ(cli::RepairSummary(repair, 5), "repair:   no changes\n");
  repair.counts[static_cast<size_t>(RepairKind::kFoldLeft)] = 3;
  repair.records.push_back({RepairKind::kFoldLeft, 10, 7, {1, 1, 1}, "facets 10 and 11 ..."});
  EXPECT_EQ(cli::RepairSummary(repair, 5),
            "repair:   no changes\n  fold_left              3\n  fold left (facet 10) at (1, 1, "
            "1): facets 10 and 11 ...\n  ... 2 more (--repair-details lists them, --stats-json "
            "has them under \"repair\")\n");
}

// A surface left open (a face missing) is what tetgen next refuses: said where nothing changed.
TEST(Report, RepairSummaryListsHolesLeftOpen) {
  RepairReport repair;
  repair.counts[static_cast<size_t>(RepairKind::kHoleLeft)] = 1;
  repair.records.push_back({RepairKind::kHoleLeft, 4, 2, {0.5, 0.5, 1}, "a loop of 4 open edges"});
  EXPECT_EQ(cli::RepairSummary(repair, 5),
            "repair:   no changes\n  hole_left              1\n  hole left open (facet 4) at "
            "(0.5, 0.5, 1): a loop of 4 open edges\n");
}

// Six unreferenced vertices do not hide the loose piece whose removal left them: every kind's
// first record is listed, then the others in order, in the report's order.
TEST(Report, RepairSummaryListsEveryKindsFirstRecord) {
  RepairReport repair;
  repair.counts[static_cast<size_t>(RepairKind::kUnreferencedVertex)] = 6;
  repair.counts[static_cast<size_t>(RepairKind::kLoosePiece)] = 1;
  for (int64_t v = 0; v < 6; ++v)
    repair.records.push_back({RepairKind::kUnreferencedVertex, 9, v, {0, 0, 0}, "unused"});
  repair.records.push_back({RepairKind::kLoosePiece, 9, -1, {1, 1, 1}, "1 facet"});
  EXPECT_EQ(cli::RepairSummary(repair, 3),
            absl::StrCat("repair:   7 changes (weld tolerance 0 of the diagonal = 0)\n",
                         "  unreferenced_vertex    6\n  loose_piece            1\n",
                         "  unreferenced vertex 0 (facet 9) at (0, 0, 0): unused\n",
                         "  unreferenced vertex 1 (facet 9) at (0, 0, 0): unused\n",
                         "  loose piece (facet 9) at (1, 1, 1): 1 facet\n",
                         "  ... 4 more (--repair-details lists them, --stats-json has them under "
                         "\"repair\")\n"));
}

// A part far from the origin lost the detail finer than the floats' spacing there when it was
// read: the summary says so from 1e-4 of the part's size on, and not below.
// Where the engine's positions lie is reported as figures (the readers hold a far part relative
// to an origin near it, so that no detail is lost and no warning is due).
TEST(Report, JsonSaysWhereThePositionsLie) {
  cli::RunReport r;
  r.fidelity.coordinates = {.magnitude = 3e6, .spacing = 0.25, .diagonal = 53.125};
  EXPECT_NE(cli::ReportJson(r).find("\"coordinates\": {\"magnitude\": 3000000, \"spacing\": "
                                    "0.25, \"diagonal\": 53.125}"),
            std::string::npos);
}

// The remote client's progress line: a bar toward the target, none without one (a tolerance
// run ends when its passes stop removing, which nothing tells in advance).
TEST(Report, ProgressLineHasABarOnlyTowardATarget) {
  PassStats p;
  p.pass = 250;
  p.vertices_left = 550;
  p.removed = 10;
  p.tried = 20;
  p.rejections[static_cast<int>(Reject::kMinAngle)] = 4;
  p.seconds = 0.5;
  SimplifyOptions o;
  o.ratio = 0.1;  // 450 of the 900 to remove
  EXPECT_EQ(cli::ProgressLine(p, 1000, o),
            "\r[" + std::string(15, '#') + std::string(15, '.') +
                "]  50% pass 250: 550 vertices, -10, tried 20, locks 0, rejected 4, 0.500 s\x1b[K");
  o.ratio = 0;
  EXPECT_EQ(cli::ProgressLine(p, 1000, o),
            "\rpass 250: 550 vertices, -10, tried 20, locks 0, rejected 4, 0.500 s\x1b[K");
  o.target_vertices = 1000;  // nothing to remove: no bar either
  EXPECT_EQ(cli::ProgressLine(p, 1000, o).find('%'), std::string::npos);
}

TEST(Wire, ProgressRoundTrip) {
  PassStats p;
  p.pass = 3;
  p.vertices_left = 100;
  p.removed = 20;
  p.seam_points_removed = 7;
  p.boxes_kept = 11;
  p.placed = 13;
  p.placed_on_lines = 4;
  p.rejections[static_cast<int>(Reject::kMinAngle)] = 5;
  p.cell = CellPassCounters{};
  p.cell->cache_hits = 9;
  p.cell->cache_misses = 1;
  p.ppe_cycles = 1234;
  p.spe_start_cycles = 5678;
  v1::Progress m;
  wire::ToProto(p, &m);
  EXPECT_DOUBLE_EQ(m.cache_hit_ratio(), 0.9);
  EXPECT_EQ(m.rejections().at("min_angle"), 5u);
  PassStats q = wire::FromProto(m);
  EXPECT_EQ(q.pass, 3);
  EXPECT_EQ(q.removed, 20u);
  EXPECT_EQ(q.seam_points_removed, 7u);
  EXPECT_EQ(q.boxes_kept, 11u);
  EXPECT_EQ(q.placed, 13u);
  EXPECT_EQ(q.placed_on_lines, 4u);
  EXPECT_EQ(q.rejections[static_cast<int>(Reject::kMinAngle)], 5u);
  ASSERT_TRUE(q.cell.has_value());
  EXPECT_EQ(q.cell->cache_hits, 9u);
  EXPECT_EQ(q.ppe_cycles, 1234u);
  EXPECT_EQ(q.spe_start_cycles, 5678u);
}

TEST(Wire, ChunkingKeepsMessagesSmallAndReassembles) {
  RawMesh mesh = testing::MakeTorus(300, 300);  // 90k vertices, 180k faces
  mesh.face_groups.assign(mesh.num_faces(), 7);
  wire::MeshAssembler assembler(mesh.num_vertices(), mesh.num_faces(), true);
  size_t chunks = wire::ForEachChunk(mesh, [&](v1::MeshChunk& c) {
    EXPECT_LT(c.ByteSizeLong(), 3u << 20);
    EXPECT_TRUE(assembler.Add(c).ok());
    return true;
  });
  EXPECT_GT(chunks, 1u);
  auto back = assembler.Finish();
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->positions, mesh.positions);
  EXPECT_EQ(back->triangles, mesh.triangles);
  EXPECT_EQ(back->face_groups, mesh.face_groups);
}

TEST(Wire, ChunkingCarriesFaceFields) {
  RawMesh mesh = testing::MakeTorus(300, 300);  // 180k faces: three chunks of faces
  const size_t nf = mesh.num_faces();
  mesh.face_groups.resize(nf);
  mesh.face_fields = {{"pressure", {}}, {"tau_x", {}}, {"tau_y", {}}};
  for (size_t f = 0; f < nf; ++f) {
    mesh.face_groups[f] = uint32_t(f % 11);
    for (int k = 0; k < 3; ++k) mesh.face_fields[k].values.push_back(float(f) * (k + 1) - 0.5f);
  }
  wire::MeshAssembler assembler(mesh.num_vertices(), nf, true, wire::FieldNames(mesh));
  size_t chunks = wire::ForEachChunk(mesh, [&](v1::MeshChunk& c) {
    EXPECT_LT(c.ByteSizeLong(), 3u << 20);  // with groups and three fields
    absl::Status s = assembler.Add(c);
    EXPECT_TRUE(s.ok()) << s;
    return true;
  });
  EXPECT_GT(chunks, 2u);
  auto back = assembler.Finish();
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->face_groups, mesh.face_groups);
  ASSERT_EQ(back->face_fields.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(back->face_fields[k].name, mesh.face_fields[k].name);
    EXPECT_EQ(back->face_fields[k].values, mesh.face_fields[k].values);
  }
}

// The result stream sends what ForEachChunk cuts, in order (encoded a chunk ahead on a helper
// thread), and stops at the first write that fails.
TEST(ResultStream, SendsEveryChunkInOrderAndStopsAtAFailedWrite) {
  RawMesh mesh = testing::MakeTorus(300, 300);  // 90k vertices, 180k faces: three chunks
  mesh.face_groups.assign(mesh.num_faces(), 3);
  mesh.face_fields = {{"pressure", std::vector<float>(mesh.num_faces(), 2.5f)}};
  ASSERT_EQ(wire::ChunkCount(mesh), 3u);
  wire::MeshAssembler assembler(mesh.num_vertices(), mesh.num_faces(), true,
                                wire::FieldNames(mesh));
  server::ChunkStreamTimes times;
  size_t written = 0;
  EXPECT_TRUE(server::StreamMeshChunks(
      mesh,
      [&](const v1::SimplifyResponse& r) {
        ++written;
        EXPECT_TRUE(r.has_chunk());
        EXPECT_TRUE(assembler.Add(r.chunk()).ok());
        return true;
      },
      &times));
  EXPECT_EQ(written, 3u);
  EXPECT_GT(times.encode_seconds, 0);
  auto back = assembler.Finish();
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->positions, mesh.positions);
  EXPECT_EQ(back->triangles, mesh.triangles);
  EXPECT_EQ(back->face_groups, mesh.face_groups);
  EXPECT_EQ(back->face_fields[0].values, mesh.face_fields[0].values);

  written = 0;
  EXPECT_FALSE(server::StreamMeshChunks(
      mesh,
      [&](const v1::SimplifyResponse&) {
        ++written;
        return written < 2;
      },
      &times));
  EXPECT_EQ(written, 2u);
  EXPECT_TRUE(server::StreamMeshChunks(
      RawMesh{}, [](const v1::SimplifyResponse&) { return false; }, &times));
}

TEST(Wire, AssemblerFaceFieldProblems) {
  v1::MeshChunk tri;
  for (float x : {0, 0, 0, 1, 0, 0, 0, 1, 0}) tri.add_positions(x);
  for (uint32_t i : {0u, 1u, 2u}) tri.add_indices(i);
  auto run = [&](std::vector<std::string> names, std::vector<v1::MeshChunk> chunks) {
    wire::MeshAssembler a(3, 1, false, std::move(names));
    for (const v1::MeshChunk& c : chunks)
      if (absl::Status s = a.Add(c); !s.ok()) return s;
    return a.Finish().status();
  };
  v1::MeshChunk with_p = tri;
  with_p.add_face_fields()->add_values(2.5f);
  EXPECT_TRUE(run({"p"}, {with_p}).ok());
  // Values may come in a chunk of their own.
  v1::MeshChunk only_p;
  only_p.add_face_fields()->add_values(2.5f);
  EXPECT_TRUE(run({"p"}, {tri, only_p}).ok());

  struct Case {
    std::vector<std::string> names;
    std::vector<v1::MeshChunk> chunks;
    std::string message;
  } cases[] = {
      {{"p"}, {tri}, "stream ended early: received 0 of 1 values of face field 'p'"},
      {{}, {with_p}, "chunk 1: 1 face field arrays but the spec declares 0 face fields ()"},
      {{"p", "q"}, {with_p}, "1 face field arrays but the spec declares 2 face fields (p, q)"},
      {{"p"}, {with_p, only_p}, "chunk 2: values of face field 'p' past the declared face_count 1"},
  };
  for (const Case& c : cases) {
    absl::Status s = run(c.names, c.chunks);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << c.message;
    EXPECT_NE(s.message().find(c.message), std::string::npos) << s;
  }
  v1::MeshChunk nan = tri;
  nan.add_face_fields()->add_values(std::nanf(""));
  absl::Status s = run({"p"}, {nan});
  EXPECT_NE(s.message().find("chunk 1: face field 'p': face 0 has a non-finite value"),
            std::string::npos)
      << s;
}

TEST(RequestReader, FaceFieldNames) {
  server::ServerConfig config;
  v1::JobSpec spec;
  spec.set_vertex_count(3);
  spec.set_face_count(1);
  EXPECT_TRUE(server::CheckSpec(spec, config).ok());
  for (const char* name : {"pressure", "tau_x", "tau_y"}) spec.add_face_field_names(name);
  EXPECT_TRUE(server::CheckSpec(spec, config).ok());
  struct Case {
    std::vector<std::string> names;
    std::string message;
  } cases[] = {
      {{"a", "b", "c", "d"}, "spec: face_field_names: 4 face fields, at most 3"},
      {{"a", ""}, "spec: face_field_names[1] is 0 bytes (1 to 64)"},
      {{std::string(65, 'x')}, "spec: face_field_names[0] is 65 bytes (1 to 64)"},
      {{"p", "q", "p"}, "spec: face_field_names: 'p' is given twice"},
  };
  for (const Case& c : cases) {
    spec.clear_face_field_names();
    for (const std::string& n : c.names) spec.add_face_field_names(n);
    absl::Status s = server::CheckSpec(spec, config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << c.message;
    EXPECT_NE(s.message().find(c.message), std::string::npos) << s;
  }
}

TEST(RequestReader, Problems) {
  server::ServerConfig config;
  config.max_vertices = 1000;
  auto run = [&](std::vector<v1::SimplifyRequest> msgs) -> absl::Status {
    size_t i = 0;
    server::RequestReader reader(
        [&](v1::SimplifyRequest* r) {
          if (i >= msgs.size()) return false;
          *r = msgs[i++];
          return true;
        },
        config);
    auto spec = reader.ReadSpec();
    if (!spec.ok()) return spec.status();
    return reader.ReadMesh(*spec).status();
  };
  v1::SimplifyRequest spec;
  spec.mutable_spec()->set_vertex_count(3);
  spec.mutable_spec()->set_face_count(1);
  v1::SimplifyRequest tri;
  for (float x : {0, 0, 0, 1, 0, 0, 0, 1, 0}) tri.mutable_chunk()->add_positions(x);
  for (uint32_t i : {0u, 1u, 2u}) tri.mutable_chunk()->add_indices(i);
  EXPECT_TRUE(run({spec, tri}).ok());
  EXPECT_NE(run({}).message().find("before the job spec"), std::string::npos);
  EXPECT_NE(run({tri}).message().find("spec must come first"), std::string::npos);
  EXPECT_NE(run({spec, spec}).message().find("second job spec"), std::string::npos);
  EXPECT_NE(run({spec, tri, tri}).message().find("past the declared"), std::string::npos);
  EXPECT_NE(run({spec}).message().find("ended early"), std::string::npos);
  v1::SimplifyRequest big = spec;
  big.mutable_spec()->set_vertex_count(5000);
  absl::Status s = run({big});
  EXPECT_EQ(s.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(s.message().find("max_vertices"), std::string::npos);
}

TEST(JobQueue, ReservationsBoundCapacity) {
  server::JobQueue q(2);
  EXPECT_TRUE(q.TryReserve());
  EXPECT_TRUE(q.TryReserve());
  EXPECT_FALSE(q.TryReserve());
  auto a = std::make_shared<server::Job>("a", "", SimplifyOptions{}, 3, 1);
  auto b = std::make_shared<server::Job>("b", "", SimplifyOptions{}, 3, 1);
  EXPECT_TRUE(q.PushReserved(a));
  EXPECT_TRUE(q.PushReserved(b));
  EXPECT_EQ(q.Position(b.get()), 1);
  EXPECT_FALSE(q.TryReserve());
  EXPECT_TRUE(q.Remove(a.get()));
  EXPECT_EQ(q.Position(b.get()), 0);
  EXPECT_EQ(q.Pop(), b);
  EXPECT_TRUE(q.TryReserve());
  q.CancelReservation();
  q.Close();
  EXPECT_EQ(q.Pop(), nullptr);
  EXPECT_FALSE(q.TryReserve());
}

TEST(Report, JsonHasEveryField) {
  cli::RunReport r;
  r.input_vertices = 10;
  r.stop_reason = "target_reached";
  r.face_fields = {"pressure"};
  r.fidelity.input_mass.solid = true;
  PassStats p;
  p.pass = 1;
  r.passes.push_back(p);
  std::string json = cli::ReportJson(r);
  for (const char* key : {"\"input\"",
                          "\"output\"",
                          "\"engine_seconds\"",
                          "\"load_seconds\"",
                          "\"write_seconds\"",
                          "\"crossings_seconds\"",
                          "\"stop_reason\"",
                          "\"options\"",
                          "\"passes\"",
                          "\"rejections\"",
                          "\"link_condition\"",
                          "\"normal_deviation\"",
                          "\"lock_conflicts\"",
                          "\"busy_seconds\"",
                          "\"candidates\"",
                          "\"field_resultant\"",
                          "\"cost\": \"deviation\"",
                          "\"input_mass\"",
                          "\"mean_thickness\"",
                          "\"inertia_change\"",
                          "\"wall_limited_share\"",
                          "\"output_crossings\": {\"pairs\": 0, \"overlaps\": {\"pairs\": 0}, "
                          "\"folds\": {\"pairs\": 0}, \"cut_short\": false}",
                          "\"tolerance_relative\"",
                          "\"feature_angle_deg\"",
                          "\"max_field_change\"",
                          "\"fidelity\"",
                          "\"deviation_bound\"",
                          "\"feature_edges\"",
                          "\"face_data\"",
                          "\"fields\": [\"pressure\"]"})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

}  // namespace
TEST(MemoryBudget, AdmitsWhileTheEstimatesFitAndTakesThemBackWithTheLease) {
  uint64_t gauge = 99;
  server::MemoryBudget budget(100, [&gauge](uint64_t admitted) { gauge = admitted; });
  EXPECT_EQ(gauge, 0u);
  std::optional<server::MemoryBudget::Lease> a = budget.TryAdmit(60);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(gauge, 60u);
  EXPECT_FALSE(budget.TryAdmit(41).has_value());  // 60 + 41 > 100
  EXPECT_EQ(budget.admitted(), 60u);
  {
    std::optional<server::MemoryBudget::Lease> b = budget.TryAdmit(40);  // exactly full
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(budget.leases(), 2u);
    EXPECT_EQ(gauge, 100u);
    EXPECT_FALSE(budget.TryAdmit(1).has_value());
  }
  EXPECT_EQ(gauge, 60u);
  server::MemoryBudget::Lease moved = std::move(*a);
  a.reset();  // the moved-from lease gives nothing back
  EXPECT_EQ(budget.admitted(), 60u);
  EXPECT_EQ(moved.bytes(), 60u);
  EXPECT_FALSE(budget.TryAdmit(101).has_value());  // never, even when empty
}

TEST(MemoryBudget, EstimateGrowsWithTheDeclaredSizeAndWhatTheOptionsKeep) {
  SimplifyOptions native;
  const uint64_t small = server::EstimateJobBytes(1000, 2000, native);
  EXPECT_EQ(small,
            server::kJobBaseBytes + 1000 * server::kBytesPerVertex + 2000 * server::kBytesPerFace);
  EXPECT_LT(small, server::EstimateJobBytes(2000, 2000, native));
  EXPECT_LT(small, server::EstimateJobBytes(1000, 4000, native));
  SimplifyOptions cell;
  cell.backend = Backend::kCell;
  cell.cell.spes = 8;
  cell.cell.local_store_kib = 256;
  EXPECT_EQ(server::EstimateJobBytes(1000, 2000, cell),
            small + 8 * 256 * 1024 + 1000 * server::kCellBytesPerVertex);
  SimplifyOptions walls;
  walls.max_wall_share = 0.2;
  EXPECT_EQ(server::EstimateJobBytes(1000, 2000, walls), small + 2000 * server::kWallBytesPerFace);
  SimplifyOptions measured;
  measured.deviation_check = DeviationCheck::kMeasured;
  EXPECT_EQ(server::EstimateJobBytes(1000, 2000, measured),
            small + 2000 * server::kMeasuredBytesPerFace);
  SimplifyOptions imprint;
  imprint.repair.imprint = true;
  EXPECT_EQ(server::EstimateJobBytes(1000, 2000, imprint),
            small + 2000 * server::kImprintBytesPerFace);
  SimplifyOptions unite;
  unite.repair.unite_overlaps = true;
  EXPECT_EQ(server::EstimateJobBytes(1000, 2000, unite), small + 2000 * server::kUnionBytesPerFace);
}

TEST(MemoryBudget, DefaultIsThreeQuartersOfTheMemoryTheServerMayUse) {
  const uint64_t available = server::AvailableMemoryBytes();
  ASSERT_GT(available, 0u);
  server::ServerConfig c;
  ASSERT_EQ(server::NormalizeConfig(&c), "");
  EXPECT_EQ(c.memory_budget_mib, available / 4 * 3 >> 20);
  server::ServerConfig set;
  set.memory_budget_mib = 512;
  ASSERT_EQ(server::NormalizeConfig(&set), "");
  EXPECT_EQ(set.memory_budget_mib, 512u);
}

}  // namespace femsimp
