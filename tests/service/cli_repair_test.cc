// Repair end to end: `femsimp simplify` on broken inputs (flipped, duplicate and degenerate
// facets, a crack) locally and through the in-process server, strict mode (--repair off), and
// the server's Result and metrics.

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <google/protobuf/util/message_differencer.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/args.h"
#include "client/exit_codes.h"
#include "client/local_run.h"
#include "client/remote_call.h"
#include "client/remote_run.h"
#include "engine/crossings.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "engine/mesh_checks.h"
#include "engine/seams.h"
#include "gtest/gtest.h"
#include "tests/service/test_util.h"
#include "tests/support/files.h"

namespace femsimp {
namespace {

constexpr int kN = 24, kM = 12;

#define EXPECT_HAS(text, part)                                                                 \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (part) << "' not in:\n" \
                                                             << (text)

class CliRepairTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    input_ = WriteSoup("broken.off", testing::BrokenTorus(kN, kM));
  }

  // Runs `femsimp simplify ARGS... --threads THREADS` in process (remote with --server); stdout and
  // stderr captured.
  int Run(std::vector<std::string> args, const char* threads = "2") {
    args.insert(args.begin(), {"femsimp", "simplify"});
    args.insert(args.end(), {"--threads", threads, "--quiet"});
    absl::StatusOr<cli::Command> cmd = cli::ParseCommandLine(args);
    EXPECT_TRUE(cmd.ok()) << cmd.status();
    if (!cmd.ok()) return -1;
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    const int code =
        cmd->simplify.server.empty() ? cli::RunLocal(cmd->simplify) : cli::RunRemote(cmd->simplify);
    out_ = ::testing::internal::GetCapturedStdout();
    err_ = ::testing::internal::GetCapturedStderr();
    return code;
  }

  std::string input_, out_, err_;
};

TEST_F(CliRepairTest, BrokenInputIsRepairedAndReported) {
  ASSERT_EQ(Run({input_, Path("out.off"), "--ratio", "0.5", "--stats-json", Path("s.json")}),
            cli::kExitOk)
      << err_;
  absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
  ASSERT_TRUE(out.ok()) << out.status();
  ASSERT_TRUE(Mesh::Build(*out).ok());
  const SoupTopology t = TopologyOf(*out);
  EXPECT_EQ(t.boundary_edges, 0);  // the crack is closed
  const testing::BrokenTorusRepairs want = testing::BrokenTorusRepairsOf(kM);
  // One line per kind with its count, then the first records with facet and coordinates.
  EXPECT_HAS(out_, "repair:   " +
                       std::to_string(want.welded + want.stitched + want.flipped + want.duplicate +
                                      want.degenerate) +
                       " changes (weld tolerance 1e-07 of the diagonal");
  EXPECT_HAS(out_, "  welded_vertex          12\n");
  EXPECT_HAS(out_, "  stitched_edge          12\n");
  EXPECT_HAS(out_, "  degenerate_facet       1\n");
  EXPECT_HAS(out_, "  duplicate_facet        1\n");
  EXPECT_HAS(out_, "  flipped_facet          2\n");
  EXPECT_HAS(out_, "  welded vertex 288 (facet ");
  EXPECT_HAS(out_, " more (--repair-details lists them");
  // --stats-json: counts per kind, the tolerance, every record.
  const std::string json = testing::ReadFileBytes(Path("s.json"));
  EXPECT_HAS(json,
             "\"repair\": {\"mode\": \"on\", \"changes\": 28, \"counts\": {\"welded_vertex\": "
             "12, \"stitched_edge\": 12, \"degenerate_facet\": 1, \"split_edge\": 0, "
             "\"duplicate_facet\": 1, \"flipped_facet\": 2,");
  EXPECT_HAS(json, "\"weld_tolerance\": 1e-07");
  EXPECT_HAS(json, "{\"kind\": \"flipped_facet\", \"facet\": 10, ");
  EXPECT_HAS(json, "\"repair\": \"on\", \"weld_tolerance\": 1e-07");  // the options
  size_t records = 0;
  for (size_t at = json.find("{\"kind\": "); at != std::string::npos;
       at = json.find("{\"kind\": ", at + 1))
    ++records;
  EXPECT_EQ(records, 28u);

  // --repair-details lists every record in the summary.
  ASSERT_EQ(Run({input_, Path("out2.off"), "--ratio", "0.5", "--repair-details"}), cli::kExitOk);
  EXPECT_HAS(out_, "flipped facet 3 at (");
  EXPECT_HAS(out_, "flipped facet 10 at (");
  EXPECT_EQ(out_.find(" more (--repair-details"), std::string::npos) << out_;
}

TEST_F(CliRepairTest, EveryFormatIsRepairedAlike) {
  // A degenerate STL facet (two equal corners) or OBJ face is the repair's business, not a read
  // error: every format gives the same report.
  for (const char* ext : {".obj", ".stl", ".ply"}) {
    const std::string in = WriteSoup(std::string("broken") + ext, testing::BrokenTorus(kN, kM));
    ASSERT_EQ(Run({in, Path("out.off"), "--ratio", "0.5"}), cli::kExitOk) << ext << ": " << err_;
    EXPECT_HAS(out_, "  degenerate_facet       1\n");
    EXPECT_HAS(out_, "  duplicate_facet        1\n");
    EXPECT_HAS(out_, "  flipped_facet          2\n");
  }
}

TEST_F(CliRepairTest, CleanInputIsUnchanged) {
  ASSERT_TRUE(WriteMeshFile(Path("torus.off"), testing::MakeTorus(kN, kM)).ok());
  // One thread: the same input gives the same output (repair on and off).
  ASSERT_EQ(Run({Path("torus.off"), Path("a.off"), "--ratio", "0.5"}, "1"), cli::kExitOk);
  EXPECT_HAS(out_, "repair:   no changes\n");
  ASSERT_EQ(Run({Path("torus.off"), Path("b.off"), "--ratio", "0.5", "--repair", "off"}, "1"),
            cli::kExitOk);
  EXPECT_TRUE(testing::ReadFileBytes(Path("a.off")) == testing::ReadFileBytes(Path("b.off")));
}

TEST_F(CliRepairTest, StrictModeNamesEveryDefect) {
  ASSERT_EQ(Run({input_, Path("out.off"), "--repair", "off"}), cli::kExitInputInvalid);
  EXPECT_HAS(err_, "is not a valid mesh: repair is off and the mesh has ");
  // Every defect, each with its kind, facet and coordinates.
  // Every defect validation refuses, each with its kind, facet and coordinates (a crack is an
  // open boundary, which a valid mesh may have: strict mode leaves it).
  EXPECT_HAS(err_,
             "the mesh has 4 defects (1 degenerate facet, 1 duplicate facet, 2 flipped "
             "facets):\n");
  EXPECT_HAS(err_, "  degenerate facet 577 at (3.95456775, 0.345092058, 0): repeats a vertex");
  EXPECT_HAS(err_, "  duplicate facet 576 at (");
  EXPECT_HAS(err_, "  flipped facet 3 at (");
  EXPECT_HAS(err_, "  flipped facet 10 at (");
  EXPECT_EQ(err_.find(" more "), std::string::npos) << err_;
  EXPECT_FALSE(std::filesystem::exists(Path("out.off")));
}

// A file name or file content with escape sequences reaches the terminal escaped (\x1b), never
// as raw control bytes.
TEST_F(CliRepairTest, ControlCharactersInMessagesAreEscaped) {
  const std::string bad = Path("colour.off");
  {
    std::ofstream f(bad);
    f << "OFF\n1 1 0\n0 0 \x1b[31mred\n";
  }
  ASSERT_EQ(Run({bad, Path("out.off")}), cli::kExitInputUnreadable) << err_;
  EXPECT_HAS(err_, "\\x1b[31mred");
  EXPECT_EQ(err_.find('\x1b'), std::string::npos) << err_;
  ASSERT_EQ(Run({Path("a\x1b]0;title\x07.off"), Path("out.off")}), cli::kExitInputUnreadable);
  EXPECT_HAS(err_, "a\\x1b]0;title\\x07.off");
  EXPECT_EQ(err_.find('\x1b'), std::string::npos) << err_;
  EXPECT_EQ(err_.find('\x07'), std::string::npos) << err_;
}

// ------------------------------------------------------------------------- through the server

TEST_F(CliRepairTest, ServerRepairsAndReportsInResultAndMetrics) {
  testing::InProcessServer s;
  const RawMesh in = testing::BrokenTorus(kN, kM);
  grpc::ClientContext ctx;
  // The stream carries the report once the upload is repaired, before any pass.
  std::vector<std::string> stream;
  v1::RepairReport streamed;
  cli::RemoteCallbacks cb;
  cb.on_repair = [&](const v1::RepairReport& r) {
    stream.push_back("repair");
    streamed = r;
  };
  cb.on_progress = [&](const v1::Progress&) { stream.push_back("progress"); };
  cli::RemoteOutcome out =
      cli::RemoteSimplify(s.stub(), ctx, testing::RatioSpec(0.5), in, cb, true);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  ASSERT_GE(stream.size(), 2u);
  EXPECT_EQ(stream.front(), "repair");
  EXPECT_EQ(std::count(stream.begin(), stream.end(), "repair"), 1);
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(streamed, out.result.repair()));
  EXPECT_TRUE(Mesh::Build(out.output).ok());
  EXPECT_EQ(TopologyOf(out.output).boundary_edges, 0);
  const v1::RepairReport& r = out.result.repair();
  EXPECT_EQ(r.counts().at("welded_vertex"), 12u);
  EXPECT_EQ(r.counts().at("stitched_edge"), 12u);
  EXPECT_EQ(r.counts().at("flipped_facet"), 2u);
  EXPECT_EQ(r.counts().at("duplicate_facet"), 1u);
  EXPECT_EQ(r.counts().at("degenerate_facet"), 1u);
  EXPECT_EQ(r.counts().at("split_vertex"), 0u);
  EXPECT_EQ(r.counts().at("split_edge"), 0u);  // every kind of change, 0 included
  EXPECT_EQ(r.weld_tolerance(), 1e-7);
  EXPECT_NEAR(r.weld_tolerance_abs(), 1e-7 * r.diagonal(), 1e-15);
  ASSERT_EQ(r.records_size(), 28);
  bool flipped10 = false;
  for (const v1::RepairRecord& rec : r.records()) {
    EXPECT_EQ(rec.at_size(), 3);
    flipped10 |= rec.kind() == "flipped_facet" && rec.facet() == 10;
  }
  EXPECT_TRUE(flipped10);

  const auto metrics =
      testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"));
  EXPECT_EQ(metrics.at("femsimp_repairs_total{kind=\"flipped_facet\"}"), 2);
  EXPECT_EQ(metrics.at("femsimp_repairs_total{kind=\"welded_vertex\"}"), 12);
  EXPECT_EQ(metrics.count("femsimp_repairs_total{kind=\"split_vertex\"}"), 0u);

  // A clean mesh: nothing changed, nothing counted.
  grpc::ClientContext ctx2;
  out = cli::RemoteSimplify(s.stub(), ctx2, testing::RatioSpec(0.5), testing::MakeTorus(kN, kM));
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_EQ(out.result.repair().counts().at("flipped_facet"), 0u);
  EXPECT_EQ(out.result.repair().records_size(), 0);
  EXPECT_EQ(testing::ParseMetrics(testing::HttpGet(s.server().metrics_port(), "/metrics"))
                .at("femsimp_repairs_total{kind=\"flipped_facet\"}"),
            2);
}

// Status messages are bounded (issue 15, item 4): a strict refusal of a mesh with thousands of
// defects of four kinds names five of each and the counts (2.3 KB), well inside gRPC's 8 KiB
// trailer.
TEST_F(CliRepairTest, ServerStrictRefusalOfThousandsOfDefectsIsBounded) {
  testing::InProcessServer s;
  v1::JobSpec spec = testing::RatioSpec(0.5);
  spec.mutable_options()->set_repair(v1::REPAIR_MODE_OFF);
  RawMesh mesh = testing::MakeTorus(100, 100);
  const size_t faces = mesh.num_faces();
  for (size_t f = 0; f < faces; f += 7) mesh.triangles[3 * f + 2] = mesh.triangles[3 * f];
  for (size_t f = 1; f < faces; f += 7)  // duplicates of faces that stay whole
    mesh.triangles.insert(mesh.triangles.end(), mesh.triangles.begin() + 3 * f,
                          mesh.triangles.begin() + 3 * f + 3);
  for (size_t f = 3; f < faces; f += 7) std::swap(mesh.triangles[3 * f], mesh.triangles[3 * f + 1]);
  grpc::ClientContext ctx;
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, mesh);
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  const std::string& m = out.status.error_message();
  EXPECT_HAS(m, "invalid mesh: repair is off and the mesh has ");
  EXPECT_HAS(m, absl::StrCat("(", (faces + 6) / 7, " degenerate facets"));
  EXPECT_HAS(m, "and 2853 more degenerate facets");
  EXPECT_LE(m.size(), 6100u) << m.size() << " bytes";
}

TEST_F(CliRepairTest, ServerStrictModeIsRefusedByNameAndSeamsAreKept) {
  testing::InProcessServer s;
  v1::JobSpec spec = testing::RatioSpec(0.5);
  spec.mutable_options()->set_repair(v1::REPAIR_MODE_OFF);
  grpc::ClientContext ctx;
  cli::RemoteOutcome out = cli::RemoteSimplify(s.stub(), ctx, spec, testing::BrokenTorus(kN, kM));
  EXPECT_EQ(out.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_HAS(out.status.error_message(),
             "invalid mesh: repair is off and the mesh has 4 defects (1 degenerate facet, 1 "
             "duplicate facet, 2 flipped facets): degenerate facet 577 at (");
  EXPECT_HAS(out.status.error_message(), "flipped facet 10 at (");

  // Three facets on one edge (a seam of an assembly): kept, as the same non-manifold edge.
  RawMesh hinge;
  hinge.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  hinge.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  grpc::ClientContext ctx2;
  out = cli::RemoteSimplify(s.stub(), ctx2, testing::RatioSpec(0.5), hinge);
  ASSERT_TRUE(out.status.ok()) << out.status.error_message();
  EXPECT_EQ(out.output.num_faces(), 3u);
  // The output's numbering is the engine's (curve order): the edge is found by its ends' places.
  const std::vector<EdgeUse> seams = NonManifoldEdges(out.output);
  ASSERT_EQ(seams.size(), 1u);
  EXPECT_EQ(seams[0].faces, 3u);
  const auto at = [&](uint32_t v) {
    return std::array<float, 3>{out.output.positions[3 * v], out.output.positions[3 * v + 1],
                                out.output.positions[3 * v + 2]};
  };
  std::array<std::array<float, 3>, 2> ends = {at(seams[0].a), at(seams[0].b)};
  std::sort(ends.begin(), ends.end());
  EXPECT_EQ(ends, (std::array<std::array<float, 3>, 2>{{{0, 0, 0}, {1, 0, 0}}}));
  // The same locally.
  ASSERT_EQ(Run({WriteSoup("hinge.off", hinge), Path("out.off")}), cli::kExitOk) << err_;
}

// A part in global coordinates far from the origin (a bolt in plant coordinates, 2 million units
// out, where floats are 2^-3 apart): the reader holds it relative to an origin near it, so
// nothing of the file is rounded away and no warning is due, and the vertices the simplification
// kept are written as the file had them, every digit, locally and through the server (the spec
// and the result carry the origin).
TEST_F(CliRepairTest, APartFarFromTheOriginKeepsItsDigitsLocallyAndThroughTheServer) {
  const RawMesh box = testing::MakeBox({8, 6, 4}, {4, 3, 2});
  std::string off = absl::StrCat("OFF\n", box.num_vertices(), " ", box.num_faces(), " 0\n");
  std::vector<std::string> lines;
  for (size_t v = 0; v < box.num_vertices(); ++v) {
    lines.push_back(absl::StrFormat("%.4f %.4f %.4f", 1000000.0371 + box.positions[3 * v],
                                    2000000.0813 + box.positions[3 * v + 1],
                                    -300000.0529 + box.positions[3 * v + 2]));
    absl::StrAppend(&off, lines.back(), "\n");
  }
  for (size_t f = 0; f < box.num_faces(); ++f)
    absl::StrAppend(&off, "3 ", box.triangles[3 * f], " ", box.triangles[3 * f + 1], " ",
                    box.triangles[3 * f + 2], "\n");
  const std::string far = Path("far.off");
  std::ofstream(far) << off;
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    std::vector<std::string> args = {far, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    EXPECT_EQ(out_.find("far from the origin"), std::string::npos) << out_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    ASSERT_LT(out->num_vertices(), box.num_vertices());
    // Every output vertex line is one of the input's, as written.
    const std::string text = testing::ReadFileBytes(Path("out.off"));
    size_t pos = text.find('\n', text.find('\n') + 1) + 1;
    for (size_t v = 0; v < out->num_vertices(); ++v) {
      const size_t end = text.find('\n', pos);
      const std::string line = text.substr(pos, end - pos);
      EXPECT_NE(std::find(lines.begin(), lines.end(), line), lines.end())
          << (remote ? "remote" : "local") << ": output vertex " << v << " '" << line << "'";
      pos = end + 1;
    }
  }
}

// Binary STL holds absolute floats: the far part's corners round there, and the summary and
// --stats-json say by how much and which formats keep them; an STL of named solids (ASCII) and
// the other formats keep every digit and say nothing.
TEST_F(CliRepairTest, BinaryStlOfAFarPartSaysItRounds) {
  RawMesh box = testing::MakeBox({8, 6, 4}, {4, 3, 2});
  std::string off = absl::StrCat("OFF\n", box.num_vertices(), " ", box.num_faces(), " 0\n");
  for (size_t v = 0; v < box.num_vertices(); ++v)
    absl::StrAppend(&off, absl::StrFormat("%.4f %.4f %.4f\n", 1000000.0371 + box.positions[3 * v],
                                          2000000.0813 + box.positions[3 * v + 1],
                                          -300000.0529 + box.positions[3 * v + 2]));
  for (size_t f = 0; f < box.num_faces(); ++f)
    absl::StrAppend(&off, "3 ", box.triangles[3 * f], " ", box.triangles[3 * f + 1], " ",
                    box.triangles[3 * f + 2], "\n");
  std::ofstream(Path("far.off")) << off;
  ASSERT_EQ(Run({Path("far.off"), Path("out.stl"), "--stats-json", Path("s.json")}), cli::kExitOk)
      << err_;
  EXPECT_HAS(out_, "\nwarning:  binary STL holds absolute float coordinates: far from the origin");
  EXPECT_HAS(out_, "write .ply, .obj, .off or .msh to keep every digit\n");
  EXPECT_HAS(testing::ReadFileBytes(Path("s.json")),
             "\"warnings\": [\"binary STL holds absolute float coordinates");
  // The figure is what the file lost: its corners against the same run's exact PLY.
  const size_t at = out_.find("moved by up to ") + 15;
  const double said = std::stod(out_.substr(at));
  ASSERT_EQ(Run({Path("far.off"), Path("out.ply")}), cli::kExitOk) << err_;
  EXPECT_EQ(out_.find("binary STL"), std::string::npos) << out_;
  absl::StatusOr<RawMesh> stl = ReadMeshFile(Path("out.stl"));
  absl::StatusOr<RawMesh> ply = ReadMeshFile(Path("out.ply"));
  ASSERT_TRUE(stl.ok() && ply.ok());
  double worst = 0.0;
  for (size_t c = 0; c < ply->positions.size(); ++c) {
    const double exact = ply->origin[c % 3] + double(ply->positions[c]);
    worst = std::max(worst, std::abs(double(float(exact)) - exact));
  }
  EXPECT_GT(worst, 0.0);
  EXPECT_NEAR(said, worst, 1e-6 * worst);
  EXPECT_EQ(stl->num_faces(), ply->num_faces());
}

// Two boxes through each other in one file (a thin wall exported with facets as large as the
// part crosses itself alike): repair cannot untangle them, the simplification keeps them and
// makes no more, and the summary, --stats-json and the server's Result say where OUT crosses
// itself before a mesher refuses it.
TEST_F(CliRepairTest, AnOutputThatIntersectsItselfIsReportedLocallyAndByTheServer) {
  RawMesh boxes = testing::MakeBox({1, 1, 1}, {6, 6, 6});
  testing::Append(boxes, testing::MakeBox({1, 1, 1}, {6, 6, 6}), {0.5f, 0.25f, 0.25f});
  const std::string crossing = WriteSoup("crossing.off", boxes);
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    std::vector<std::string> args = {crossing, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    const SoupCrossings c = FindCrossings(*out);
    ASSERT_GT(c.pairs, 0u);
    EXPECT_LT(out->num_faces(), boxes.num_faces());
    EXPECT_HAS(out_,
               absl::StrFormat("warning:  OUT intersects itself: %u face pairs cross (the first: "
                               "faces %u and %u, at (",
                               c.pairs, c.face_a, c.face_b));
    EXPECT_HAS(out_, "the input's own crossings, kept (the simplification makes none)");
    EXPECT_HAS(out_, "  crossing_left          1\n");
    EXPECT_HAS(out_, "two surfaces cross each other (");
    if (!remote) {
      EXPECT_HAS(out_, "), crossings check ");  // its cost, beside the engine's
    }
    EXPECT_HAS(testing::ReadFileBytes(Path("s.json")),
               absl::StrCat("\"output_crossings\": {\"pairs\": ", c.pairs, ", \"faces\": [",
                            c.face_a, ", ", c.face_b, "]"));
  }
  // A clean input: no warning, and the count says none.
  ASSERT_EQ(Run({input_, Path("out.off"), "--stats-json", Path("s.json")}), cli::kExitOk) << err_;
  EXPECT_EQ(out_.find("intersects itself"), std::string::npos) << out_;
  EXPECT_HAS(testing::ReadFileBytes(Path("s.json")),
             "\"output_crossings\": {\"pairs\": 0, \"overlaps\": {\"pairs\": 0}, \"folds\": "
             "{\"pairs\": 0}, \"cut_short\": false}");
}

// A soup of facets crossing each other everywhere (millions of pairs; counting them all took
// 34 s for 20,000 facets): the repair and the output's check stop counting at 100,000 pairs and
// say so, locally and through the server.
TEST_F(CliRepairTest, ASoupCrossingItselfEverywhereIsCountedToAFloor) {
  const std::string soup = WriteSoup("soup.off", testing::RandomSoup(3000, 4242));
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {soup, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    EXPECT_HAS(out_, "warning:  OUT intersects itself: at least ");
    EXPECT_HAS(out_,
               " face pairs cross (the check stopped there: a soup of facets, or bodies "
               "exported overlapping; the first it found: faces ");
    EXPECT_HAS(out_, "more than 100000 face pairs cross; left as they are");
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"cut_short\": true}");
    const size_t at = json.find("\"output_crossings\": {\"pairs\": ");
    ASSERT_NE(at, std::string::npos) << json;
    EXPECT_GT(std::stoull(json.substr(at + 30)), 100000u) << json.substr(at, 80);
  }
}

// A vertex written wrongly, its facets through the part's far wall: repair takes it out with
// its facets and closes its ring, locally and through the server; the output crosses nowhere.
TEST_F(CliRepairTest, AVertexThroughTheFarWallIsTakenOutLocallyAndByTheServer) {
  RawMesh slab = testing::MakeBox({4, 4, 1}, {4, 4, 1});
  for (uint32_t v = 0; v < slab.num_vertices(); ++v)
    if (slab.positions[3 * v] == 2 && slab.positions[3 * v + 1] == 2 &&
        slab.positions[3 * v + 2] == 1) {
      slab.positions[3 * v] = 2.1f;
      slab.positions[3 * v + 1] = 2.2f;
      slab.positions[3 * v + 2] = -0.5f;
    }
  ASSERT_GT(FindCrossings(slab).pairs, 0u);
  const std::string spiked = WriteSoup("spiked.off", slab);
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {spiked, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(FindCrossings(*out).pairs, 0u);
    EXPECT_HAS(out_, "  crossing_removed       1\n");
    EXPECT_HAS(out_,
               "facets of one surface crossed each other: 6 facets around them taken out "
               "(1 vertex with them, the farthest 1.5 off the new facets)");
    EXPECT_EQ(out_.find("intersects itself"), std::string::npos) << out_;
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"crossing_removed\": 1,");
    EXPECT_HAS(json, "\"output_crossings\": {\"pairs\": 0,");
  }
}

// A stray facet written with a solid: removed, locally and by the server, so that the part keeps
// its volume (and the volume budget its meaning); --loose-piece-share 0 keeps it, and the part is
// then an open surface.
TEST_F(CliRepairTest, AStrayFacetBesideASolidIsRemovedLocallyAndByTheServer) {
  RawMesh part = testing::MakeBox({4, 4, 1}, {4, 4, 1});
  const uint32_t b = static_cast<uint32_t>(part.num_vertices());
  part.positions.insert(part.positions.end(), {6, 6, 3, 6.5f, 6, 3, 6, 6.5f, 3});
  part.triangles.insert(part.triangles.end(), {b, b + 1, b + 2});
  const std::string stray = WriteSoup("stray.off", part);
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {stray, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(TopologyOf(*out).boundary_edges, 0);
    EXPECT_HAS(out_, "  loose_piece            1\n");
    EXPECT_HAS(out_,
               "1 facet of area 0.125 (0.26% of the bodies' area), open and joined "
               "to nothing: removed");
    EXPECT_HAS(out_, "mass:     volume 16 -> 16");
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"loose_piece\": 1,");
    EXPECT_HAS(json, "\"kind\": \"loose_piece\"");

    args.insert(args.end(), {"--loose-piece-share", "0"});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    EXPECT_EQ(out_.find("loose_piece"), std::string::npos) << out_;
    EXPECT_HAS(out_, "mass:     area (open surface)");
  }
}

// A part written twice, the copy tessellated anew and moved by a placement's rounding: the copy
// is removed, locally and by the server, so that the volume counts once and nothing crosses;
// --duplicate-body-offset 0 keeps both, which then cross.
TEST_F(CliRepairTest, ABodyWrittenTwiceKeepsOneCopyLocallyAndByTheServer) {
  RawMesh part = testing::MakeBox({4, 4, 1}, {4, 4, 1});
  testing::Append(part, testing::MakeBox({4, 4, 1}, {2, 3, 1}), {0.02f, 0.01f, 0.005f});
  const std::string twice = WriteSoup("twice.off", part);
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {twice, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(FindCrossings(*out).pairs, 0u);
    EXPECT_HAS(out_, "  duplicate_body         1\n");
    EXPECT_HAS(out_,
               "closed body of 44 facets (volume 16) repeats the body of 96 facets at facet 0: "
               "each lies within 0.0229 of the other");
    EXPECT_HAS(out_, "mass:     volume 16 -> 16");
    EXPECT_EQ(out_.find("intersects itself"), std::string::npos) << out_;
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"duplicate_body\": 1,");
    EXPECT_HAS(json, "\"kind\": \"duplicate_body\"");

    args.insert(args.end(), {"--duplicate-body-offset", "0"});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    EXPECT_EQ(out_.find("duplicate_body"), std::string::npos) << out_;
    EXPECT_HAS(out_, "mass:     volume 32 -> ");
  }
}

// A box 2 x 2 x 2 inside a coating 1 thick, each body written closed: the box's surface comes
// twice, facing both ways. `seam_aside`: two unit cubes beside them share an edge (a seam).
RawMesh CoatedBox(bool seam_aside) {
  RawMesh coated = testing::MakeBox({4, 4, 4}, {4, 4, 4});
  testing::Append(coated, testing::MakeBox({2, 2, 2}, {2, 2, 2}), {1, 1, 1});
  RawMesh turned = testing::MakeBox({2, 2, 2}, {2, 2, 2});
  for (size_t f = 0; f < turned.num_faces(); ++f)
    std::swap(turned.triangles[3 * f + 1], turned.triangles[3 * f + 2]);
  testing::Append(coated, turned, {1, 1, 1});
  if (seam_aside) {
    testing::Append(coated, testing::MakeBox({1, 1, 1}, {1, 1, 1}), {10, 0, 0});
    testing::Append(coated, testing::MakeBox({1, 1, 1}, {1, 1, 1}), {11, 1, 0});
  }
  return coated;
}

// Faces whose three vertices another face has, in the other order.
size_t FacesWrittenBothWays(const RawMesh& m) {
  std::set<std::array<uint32_t, 3>> faces;
  const auto key = [&](size_t f, bool turned) {
    const uint32_t* t = &m.triangles[3 * f];
    std::array<uint32_t, 3> k =
        turned ? std::array{t[0], t[2], t[1]} : std::array{t[0], t[1], t[2]};
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    return k;
  };
  for (size_t f = 0; f < m.num_faces(); ++f) faces.insert(key(f, false));
  size_t both = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) both += faces.contains(key(f, true));
  return both;
}

// The box's surface is kept and simplified once, and each body is a part: the mass counts both,
// and the output has the surface twice again, each body closed on its own as in the input
// (read again, it is the same assembly), locally and through the server.
TEST_F(CliRepairTest, ABodyInsideAnotherSharingItsSurfaceIsAPartLocallyAndByTheServer) {
  const std::string input = WriteSoup("coated.off", CoatedBox(false));
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {input, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    EXPECT_HAS(out_, "  shared_shell           1\n");
    EXPECT_HAS(out_, "mass:     volume 64 -> 64,");
    EXPECT_HAS(out_, "parts:    2 solids of an assembly, volume each: part 1 56 -> 56 (");
    EXPECT_HAS(out_, ", part 2 8 -> 8 (");
    EXPECT_EQ(out_.find("warning:  the volume"), std::string::npos) << out_;
    EXPECT_HAS(testing::ReadFileBytes(Path("s.json")), "\"kind\": \"shared_shell\"");
    const absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    const size_t inner_faces = FacesWrittenBothWays(*out);
    EXPECT_GE(inner_faces, 12u);  // the box's, at least two per side
    EXPECT_EQ(inner_faces % 2, 0u);
    EXPECT_NEAR(testing::SignedVolume(*out), 64.0, 1e-9);

    ASSERT_EQ(Run({Path("out.off"), Path("again.off")}), cli::kExitOk) << err_;
    EXPECT_HAS(out_, "  shared_shell           1\n");
    EXPECT_HAS(out_, "mass:     volume 64 -> 64,");
  }
}

// Where the mesh has seams too, no parts are made for the box (the seam parts and these would
// need one numbering): the summary says the box is out of the mass, by the mass line.
TEST_F(CliRepairTest, ABodyInsideAnotherBesideASeamIsSaidLeftOut) {
  const std::string input = WriteSoup("coated.off", CoatedBox(true));
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {input, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    EXPECT_HAS(out_, "  shared_shell_left      1\n");
    EXPECT_HAS(out_,
               "warning:  the volume, the moments and the mass budgets leave out 1 body inside "
               "another that shares its whole surface with it");
    EXPECT_HAS(testing::ReadFileBytes(Path("s.json")), "\"kind\": \"shared_shell_left\"");
  }
}

// A block 2 x 1 x 2 standing on a plate 4 x 3 x 1, exported apart: the contact (area 2)
// triangulated by both, no vertex shared.
RawMesh StackedBoxes() {
  RawMesh stacked = testing::MakeBox({4, 3, 1}, {4, 3, 1});
  testing::Append(stacked, testing::MakeBox({2, 1, 2}, {3, 2, 2}), {0.5f, 0.5f, 1.0f});
  return stacked;
}

// A block standing on a plate, the two exported apart (each triangulates the contact its own
// way): nothing crosses, yet a mesher refuses the faces that overlap in the contact's plane. The
// summary, --stats-json and the server's Result say so, with the contact's area.
TEST_F(CliRepairTest, BodiesTouchingWithoutSharedVerticesAreReportedLocallyAndByTheServer) {
  const std::string input = WriteSoup("stacked.off", StackedBoxes());
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    std::vector<std::string> args = {input, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    const SoupCrossings c = FindCrossings(*out);
    EXPECT_EQ(c.pairs, 0u);
    ASSERT_GT(c.overlaps.pairs, 0u);
    EXPECT_NEAR(c.overlaps.area, 2.0, 1e-6);
    EXPECT_HAS(out_, absl::StrFormat("warning:  OUT has overlapping faces: %u face pairs overlap "
                                     "in their plane, over an area of 2 (the first: faces %u and "
                                     "%u, at (",
                                     c.overlaps.pairs, c.overlaps.face_a, c.overlaps.face_b));
    EXPECT_EQ(out_.find("intersects itself"), std::string::npos) << out_;
    EXPECT_HAS(testing::ReadFileBytes(Path("s.json")),
               absl::StrCat("\"output_crossings\": {\"pairs\": 0, \"overlaps\": {\"pairs\": ",
                            c.overlaps.pairs, ", \"area\": 2, \"faces\": [", c.overlaps.face_a,
                            ", ", c.overlaps.face_b, "]"));
  }
}

// A facet turned over onto its neighbours (a quad given its wrong diagonal) is unfolded by
// repair, locally and through the server. Where the facets lie in different face groups no flip
// may move the groups' border: the fold is kept, the repair summary lists it though nothing
// changed, and the output's warning and --stats-json name the first pair.
TEST_F(CliRepairTest, FoldsAreUnfoldedOrReportedLocallyAndByTheServer) {
  const std::string plain = WriteSoup("fold.off", testing::CubeWithAFoldOnTop());
  RawMesh grouped_mesh = testing::CubeWithAFoldOnTop();
  for (uint32_t f = 0; f < grouped_mesh.num_faces(); ++f) grouped_mesh.face_groups.push_back(f);
  const std::string grouped = Path("fold_groups.ply");
  ASSERT_TRUE(WriteMeshFile(grouped, grouped_mesh).ok());
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    SCOPED_TRACE(remote ? "remote" : "local");
    std::vector<std::string> args = {plain, Path("out.off"), "--stats-json", Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(FindCrossings(*out).folds.pairs, 0u);
    EXPECT_HAS(out_, "  unfolded_edge          1\n");
    EXPECT_HAS(out_,
               "folded edge (facet 10) at (1, 1, 1): to (0, 0, 1): facets 10 and 11 lie on "
               "each other in their plane, one turned over: edge replaced by the other "
               "diagonal");
    EXPECT_EQ(out_.find("folded faces"), std::string::npos) << out_;
    std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"unfolded_edge\": 1,");
    EXPECT_HAS(json, "\"folds\": {\"pairs\": 0}");

    args = {grouped, Path("out.ply"), "--stats-json", Path("g.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    out = ReadMeshFile(Path("out.ply"));
    ASSERT_TRUE(out.ok()) << out.status();
    const SoupCrossings c = FindCrossings(*out);
    ASSERT_GT(c.folds.pairs, 0u);
    EXPECT_HAS(out_, "repair:   no changes\n  fold_left              3\n");
    EXPECT_HAS(out_, "; they belong to different face groups or carry different field values");
    EXPECT_HAS(out_, absl::StrFormat("warning:  OUT has folded faces: %u face pair%s lie on each "
                                     "other in their plane, one of each turned over (the first: "
                                     "faces %u and %u, along their common edge at (",
                                     c.folds.pairs, c.folds.pairs == 1 ? "" : "s", c.folds.face_a,
                                     c.folds.face_b));
    json = testing::ReadFileBytes(Path("g.json"));
    EXPECT_HAS(json, "\"fold_left\": 3,");
    EXPECT_HAS(json, absl::StrCat("\"folds\": {\"pairs\": ", c.folds.pairs, ", \"faces\": [",
                                  c.folds.face_a, ", ", c.folds.face_b, "]"));
  }
}

// --imprint makes the stacked boxes' contact one surface the two share, locally and through the
// server (the option travels in EngineOptions): no overlap left, two parts of their own volumes.
TEST_F(CliRepairTest, ImprintSharesTheContactLocallyAndThroughTheServer) {
  const std::string input = WriteSoup("stacked.off", StackedBoxes());
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    std::vector<std::string> args = {input, Path("out.off"), "--imprint", "--stats-json",
                                     Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    const SoupCrossings c = FindCrossings(*out);
    EXPECT_EQ(c.pairs, 0u);
    EXPECT_EQ(c.overlaps.pairs, 0u);
    EXPECT_EQ(out_.find("overlapping faces"), std::string::npos) << out_;
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"imprinted_contact\": 1,");
    EXPECT_HAS(json,
               "\"contact_left\": 0, \"hole_left\": 0, \"crossing_left\": 0, \"overlap_left\": 0, "
               "\"shared_shell_left\": 0}");
    EXPECT_HAS(json, "\"kind\": \"imprinted_contact\"");
    EXPECT_HAS(json, "bodies exported apart touch over an area of 2:");
    EXPECT_HAS(json, "{\"input_volume\": 4, ");   // the block, 2 x 1 x 2
    EXPECT_HAS(json, "{\"input_volume\": 12, ");  // the plate, 4 x 3 x 1
  }
}

// Two boxes crossing each other (a part exported as solids never fused): said and left by default;
// --unite-overlaps replaces them by their union, locally and through the server (the option
// travels in EngineOptions): no crossing left, one solid of the union's volume, 8 + 8 - 1.
TEST_F(CliRepairTest, UniteOverlapsReplacesCrossingBodiesByTheirUnion) {
  RawMesh boxes = testing::MakeBox({2, 2, 2}, {3, 3, 3});
  testing::Append(boxes, testing::MakeBox({2, 2, 2}, {3, 3, 3}), {1, 1, 1});
  const std::string input = WriteSoup("crossing.off", boxes);
  ASSERT_EQ(Run({input, Path("out.off")}), cli::kExitOk) << err_;
  EXPECT_HAS(out_, "  crossing_left          1\n");
  EXPECT_HAS(out_, "--unite-overlaps replaces closed bodies exported overlapping by their union");
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    std::vector<std::string> args = {input, Path("out.off"), "--unite-overlaps", "--stats-json",
                                     Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(FindCrossings(*out).pairs, 0u);
    EXPECT_EQ(TopologyOf(*out).boundary_edges, 0);
    EXPECT_NEAR(testing::SignedVolume(*out), 15.0, 15.0 * 0.005);  // the volume budget
    EXPECT_EQ(out_.find("intersects itself"), std::string::npos) << out_;
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"united_bodies\": 1,");
    EXPECT_HAS(json, "\"crossing_left\": 0");
    EXPECT_HAS(json, "\"unite_overlaps\": true");
    EXPECT_HAS(json, "2 bodies exported overlapping united: their 216 facets re-made as ");
    EXPECT_HAS(json, "\"input_mass\": {\"solid\": true, \"volume\": 15,");
  }
}

// A box with its top face dropped: left open and said by default; --fill-holes planar closes it
// in its plane, locally and through the server (the option travels in EngineOptions).
TEST_F(CliRepairTest, FillHolesPlanarClosesADroppedFlatFace) {
  RawMesh tray = testing::MakeBox({3, 2, 1}, {6, 4, 2});
  tray.triangles.resize(tray.triangles.size() - 3 * 2 * 6 * 4);  // the +z side comes last
  const std::string input = WriteSoup("tray.off", tray);
  ASSERT_EQ(Run({input, Path("out.off"), "--stats-json", Path("s.json")}), cli::kExitOk) << err_;
  EXPECT_HAS(out_, "  hole_left              1\n");
  EXPECT_HAS(testing::ReadFileBytes(Path("s.json")), "; --fill-holes planar fills a flat one");
  testing::InProcessServer s;
  for (const bool remote : {false, true}) {
    std::vector<std::string> args = {input,    Path("out.off"), "--fill-holes",
                                     "planar", "--stats-json",  Path("s.json")};
    if (remote) args.insert(args.end(), {"--server", s.address()});
    ASSERT_EQ(Run(args), cli::kExitOk) << err_;
    absl::StatusOr<RawMesh> out = ReadMeshFile(Path("out.off"));
    ASSERT_TRUE(out.ok()) << out.status();
    EXPECT_EQ(TopologyOf(*out).boundary_edges, 0);
    EXPECT_NEAR(testing::SignedVolume(*out), 6.0, 6.0 * 0.005);  // the volume budget
    const std::string json = testing::ReadFileBytes(Path("s.json"));
    EXPECT_HAS(json, "\"filled_hole\": 1,");
    EXPECT_HAS(
        json,
        "\"hole_left\": 0, \"crossing_left\": 0, \"overlap_left\": 0, \"shared_shell_left\": 0}");
    EXPECT_HAS(json, "\"fill_holes\": \"planar\"");
    EXPECT_HAS(json, "an opening in one plane (20 edges in 1 loop, from vertex ");
  }
}

TEST_F(CliRepairTest, RemoteRunPrintsTheServersReport) {
  testing::InProcessServer s;
  ASSERT_EQ(Run({input_, Path("out.off"), "--ratio", "0.5", "--server", s.address(), "--stats-json",
                 Path("s.json")}),
            cli::kExitOk)
      << err_;
  EXPECT_HAS(out_, "repair:   28 changes (weld tolerance 1e-07 of the diagonal");
  EXPECT_HAS(out_, "  flipped_facet          2\n");
  EXPECT_HAS(testing::ReadFileBytes(Path("s.json")), "\"flipped_facet\": 2,");
  // Strict mode through the server: INVALID_ARGUMENT, 20 + 3.
  EXPECT_EQ(Run({input_, Path("out.off"), "--repair", "off", "--server", s.address()}), 23);
  EXPECT_HAS(err_, "repair is off and the mesh has 4 defects");
}

}  // namespace
}  // namespace femsimp
