// Service pieces without a server: argument parsing, wire conversions, chunking, stream
// validation, the job queue, the stats JSON.
#include <string>
#include <vector>

#include "client/args.h"
#include "client/report.h"
#include "gtest/gtest.h"
#include "proto/wire.h"
#include "server/job_queue.h"
#include "server/request_reader.h"
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

TEST(Args, Help) {
  auto top = Parse({"--help"});
  ASSERT_TRUE(top.ok());
  EXPECT_EQ(top->kind, cli::Command::kHelp);
  auto sub = Parse({"simplify", "--help"});
  ASSERT_TRUE(sub.ok());
  for (const char* flag :
       {"--ratio", "--target-vertices", "--threads", "--max-normal-deviation", "--min-angle",
        "--candidate-fraction", "--max-passes", "--topology-only", "--backend", "--spes",
        "--ls-cache-kib", "--spe-threads", "--stats-json", "--server", "--deadline", "Exit codes"})
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
      {{"simplify", "a", "b", "--min-angle", "70"}, "min_angle"},
      {{"simplify", "a", "b", "--ratio", "0.5", "--target-vertices", "10"}, "not both"},
      {{"simplify", "a", "b", "--spes", "2"}, "needs --backend cell"},
      {{"simplify", "a", "b", "--backend", "gpu"}, "not one of native, cell"},
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

TEST(Wire, ProgressRoundTrip) {
  PassStats p;
  p.pass = 3;
  p.vertices_left = 100;
  p.removed = 20;
  p.rejections[static_cast<int>(Reject::kMinAngle)] = 5;
  p.cell = CellPassCounters{};
  p.cell->cache_hits = 9;
  p.cell->cache_misses = 1;
  v1::Progress m;
  wire::ToProto(p, &m);
  EXPECT_DOUBLE_EQ(m.cache_hit_ratio(), 0.9);
  EXPECT_EQ(m.rejections().at("min_angle"), 5u);
  PassStats q = wire::FromProto(m);
  EXPECT_EQ(q.pass, 3);
  EXPECT_EQ(q.removed, 20u);
  EXPECT_EQ(q.rejections[static_cast<int>(Reject::kMinAngle)], 5u);
  ASSERT_TRUE(q.cell.has_value());
  EXPECT_EQ(q.cell->cache_hits, 9u);
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
  auto a = std::make_shared<server::Job>("a", "", SimplifyOptions{}, 3, 1, false);
  auto b = std::make_shared<server::Job>("b", "", SimplifyOptions{}, 3, 1, false);
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
  PassStats p;
  p.pass = 1;
  r.passes.push_back(p);
  std::string json = cli::ReportJson(r);
  for (const char* key :
       {"\"input\"", "\"output\"", "\"engine_seconds\"", "\"load_seconds\"", "\"write_seconds\"",
        "\"stop_reason\"", "\"options\"", "\"passes\"", "\"rejections\"", "\"link_condition\"",
        "\"normal_deviation\"", "\"lock_conflicts\"", "\"busy_seconds\"", "\"candidates\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

}  // namespace
}  // namespace femsimp
