// Engine benchmark: femsimp (paper's geometric criteria, topology only) against OpenMesh's
// Decimater and meshoptimizer on one loaded mesh, interleaved, best of N; plus output quality.
//
// Memory: live heap bytes (bench/heap_counter.h) allocated by the engine or peer during the run,
// peak minus the level before it. The input soup (RawMesh) is loaded before and excluded.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "bench/heap_counter.h"
#include "bench/peers/peer_run.h"
#include "bench/speed_peers.h"
#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "engine/option_flags.h"
#include "engine/option_table.h"
#include "engine/simplify.h"
#include "tests/judge/judge.h"

namespace {

using femsimp::RawMesh;
using Clock = std::chrono::steady_clock;
bool g_pass_log = false;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
using femsimp::bench::LiveHeapBytes;
using femsimp::bench::PeakHeapBytes;
using femsimp::bench::ResetHeapPeak;
// Process CPU time over all threads: on a shared machine, comparing it between thread counts
// separates the engine's own parallel overhead from time lost to other processes.
using femsimp::bench::ProcessCpuSeconds;

// ---- quality ---------------------------------------------------------------------------------

struct Quality {
  size_t vertices = 0, faces = 0;  // referenced vertices only
  size_t boundary_edges = 0, nonmanifold_edges = 0;
  bool manifold = false;  // femsimp::Mesh::Build accepts it
  std::string build_error;
  double min_angle_deg = 0.0;
  double frac_below_10 = 0.0;  // share of triangles with an angle below 10 degrees
  std::string self_intersect = "not checked";
  double self_intersect_seconds = 0.0;
};

double MinAngleDeg(const float* a, const float* b, const float* c) {
  const float* p[3] = {a, b, c};
  double best = 180.0;
  for (int i = 0; i < 3; ++i) {
    const float *o = p[i], *u = p[(i + 1) % 3], *w = p[(i + 2) % 3];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) e1[k] = double(u[k]) - o[k], e2[k] = double(w[k]) - o[k];
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                 cz = e1[0] * e2[1] - e1[1] * e2[0];
    const double dot = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    best = std::min(best, std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot) * 180.0 / M_PI);
  }
  return best;
}

// Runs the CGAL check in a forked child so that a slow one can be abandoned after the limit.
void CheckSelfIntersections(const RawMesh& m, double limit_s, Quality& q) {
  if (limit_s <= 0) return;
  int fds[2];
  if (pipe(fds) != 0) return;
  const auto t0 = Clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const char r = femsimp::judge::SelfIntersects(m) ? 'y' : 'n';
    if (write(fds[1], &r, 1) != 1) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    return;
  }
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (Seconds(t0, Clock::now()) > limit_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      q.self_intersect = "not checked (>" + std::to_string(static_cast<int>(limit_s)) + " s)";
      close(fds[0]);
      return;
    }
    usleep(20000);
  }
  q.self_intersect_seconds = Seconds(t0, Clock::now());
  char r = 0;
  if (read(fds[0], &r, 1) == 1) q.self_intersect = r == 'y' ? "yes" : "no";
  close(fds[0]);
}

Quality Analyze(const RawMesh& m, double si_limit_s) {
  Quality q;
  q.faces = m.num_faces();
  std::vector<char> used(m.num_vertices(), 0);
  std::vector<uint64_t> edges;
  edges.reserve(m.triangles.size());
  double min_angle = 180.0;
  size_t below = 0;
  for (size_t f = 0; f < q.faces; ++f) {
    const uint32_t* t = &m.triangles[3 * f];
    for (int i = 0; i < 3; ++i) {
      used[t[i]] = 1;
      const uint64_t a = std::min(t[i], t[(i + 1) % 3]), b = std::max(t[i], t[(i + 1) % 3]);
      edges.push_back(a << 32 | b);
    }
    const double ang =
        MinAngleDeg(&m.positions[3 * t[0]], &m.positions[3 * t[1]], &m.positions[3 * t[2]]);
    min_angle = std::min(min_angle, ang);
    below += ang < 10.0;
  }
  q.min_angle_deg = q.faces ? min_angle : 0.0;
  q.frac_below_10 = q.faces ? double(below) / double(q.faces) : 0.0;
  q.vertices = static_cast<size_t>(std::count(used.begin(), used.end(), 1));
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    q.boundary_edges += j - i == 1;
    q.nonmanifold_edges += j - i > 2;
    i = j;
  }
  auto built = femsimp::Mesh::Build(m);
  q.manifold = built.ok();
  if (!built.ok()) q.build_error = std::string(built.status().message());
  CheckSelfIntersections(m, si_limit_s, q);
  return q;
}

// ---- runs ------------------------------------------------------------------------------------

enum class Kind { kFemsimp, kOpenMesh, kMeshopt };

struct Config {
  std::string name;  // row label
  Kind kind = Kind::kFemsimp;
  femsimp::SimplifyOptions options;  // femsimp only
  uint64_t target_vertices = 0;      // peers only
  uint64_t target_faces = 0;         // meshoptimizer only (it counts indices)
  std::string family;                // rows with the same family compare threads
};

using Sample = femsimp::bench::SpeedSample;

struct Row {
  Config config;
  std::vector<Sample> samples;
  RawMesh output;  // from the first repetition
  std::optional<femsimp::SimplifyResult> result;
  Quality quality;
  double best() const {
    double b = 1e300;
    for (const Sample& s : samples) b = std::min(b, s.seconds);
    return b;
  }
  const Sample& best_sample() const {
    return *std::min_element(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) {
      return a.seconds < b.seconds;
    });
  }
};

bool RunFemsimp(const RawMesh& in, Row& row, bool keep) {
  const int64_t live0 = LiveHeapBytes();
  ResetHeapPeak();
  Sample s;
  const auto t0 = Clock::now();
  auto mesh = femsimp::Mesh::Build(in);
  s.build_seconds = Seconds(t0, Clock::now());
  if (!mesh.ok()) {
    std::fprintf(stderr, "Mesh::Build: %s\n", std::string(mesh.status().message()).c_str());
    return false;
  }
  const int64_t build_peak = PeakHeapBytes(), live1 = LiveHeapBytes();
  ResetHeapPeak();
  const double cpu0 = ProcessCpuSeconds();
  auto result = femsimp::Simplify(*mesh, row.config.options);
  s.cpu_seconds = ProcessCpuSeconds() - cpu0;
  if (!result.ok()) {
    std::fprintf(stderr, "Simplify: %s\n", std::string(result.status().message()).c_str());
    return false;
  }
  const int64_t simp_peak = PeakHeapBytes();
  s.seconds = result->engine_seconds;
  s.work_bytes = simp_peak - live1;
  s.total_bytes = std::max(build_peak, simp_peak) - live0;
  row.samples.push_back(s);
  if (keep && g_pass_log)
    for (const auto& p : result->passes)
      std::fprintf(stderr,
                   "  [%s thr=%d] pass %d: candidates %llu tried %llu removed %llu lock %llu "
                   "inconsistent %llu left %llu %.3f s (busy %.3f s)\n",
                   row.config.name.c_str(), row.config.options.threads, p.pass,
                   (unsigned long long)p.candidates, (unsigned long long)p.tried,
                   (unsigned long long)p.removed, (unsigned long long)p.lock_conflicts,
                   (unsigned long long)p.inconsistent, (unsigned long long)p.vertices_left,
                   p.seconds, p.busy_seconds);
  if (keep) {
    row.output = mesh->ToRaw();
    row.result = *result;
  }
  return true;
}

bool RunOpenMesh(const RawMesh& in, Row& row, bool keep) {
  row.samples.push_back(femsimp::bench::RunOpenMeshDecimater(in, row.config.target_vertices,
                                                             keep ? &row.output : nullptr));
  return true;
}

bool RunMeshopt(const RawMesh& in, Row& row, bool keep) {
  row.samples.push_back(femsimp::bench::RunMeshoptSimplify(in, row.config.target_faces,
                                                           keep ? &row.output : nullptr));
  return true;
}

bool Run(const RawMesh& in, Row& row, bool keep) {
  switch (row.config.kind) {
    case Kind::kFemsimp:
      return RunFemsimp(in, row, keep);
    case Kind::kOpenMesh:
      return RunOpenMesh(in, row, keep);
    case Kind::kMeshopt:
      return RunMeshopt(in, row, keep);
  }
  return false;
}

// ---- report ----------------------------------------------------------------------------------

struct Args {
  std::string mesh, label, json;
  int repeats = 3;
  std::vector<int> threads = {1, 2};
  bool peers = true;
  std::string variant = "auto";  // min-angle-0 variant: auto (paper removes < 10 %), on, off
  double si_limit_s = 60;
  // ratio: target for topology-only and the variant (0: until the criteria stop)
  femsimp::SimplifyOptions target;
};

std::string Fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string Yes(bool b) { return b ? "yes" : "no"; }

void PrintReport(const Args& a, const RawMesh& in, const Quality& qin, double load_s,
                 const std::vector<Row>& rows, FILE* out) {
  const double nf = static_cast<double>(in.num_faces());
  std::fprintf(out, "### %s\n\n", a.label.c_str());
  std::fprintf(out,
               "Input `%s`: %zu vertices, %zu triangles, %zu boundary edges, manifold %s, min "
               "angle %.2f°, %.1f %% of triangles have an angle below 10°, self-intersections: "
               "%s. Loaded in %.2f s. Best of %d interleaved repetitions.\n\n",
               a.mesh.c_str(), in.num_vertices(), in.num_faces(), qin.boundary_edges,
               Yes(qin.manifold).c_str(), qin.min_angle_deg, 100 * qin.frac_below_10,
               qin.self_intersect.c_str(), load_s, a.repeats);
  std::fprintf(out,
               "| run | thr | out V | out F | removed V | engine s (best) | all runs s | input "
               "tri/s | speedup vs 1 thr | CPU s (best run) | build s | engine mem B/face | "
               "working mem B/face | "
               "boundary edges in/out | manifold | min angle ° | tris < 10° | self-int |\n");
  std::fprintf(out, "|---|--:|--:|--:|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|---|--:|--:|---|\n");
  for (const Row& r : rows) {
    const Config& c = r.config;
    const Sample& b = r.best_sample();
    std::string all;
    for (const Sample& s : r.samples) {
      if (!all.empty()) all += ' ';
      all += Fmt("%.3f", s.seconds);
    }
    std::string speedup = "";
    if (c.kind == Kind::kFemsimp && c.options.threads > 1)
      for (const Row& o : rows)
        if (o.config.family == c.family && o.config.kind == Kind::kFemsimp &&
            o.config.options.threads == 1)
          speedup = Fmt("%.2f×", o.best() / r.best());
    const int thr = c.kind == Kind::kFemsimp ? c.options.threads : 1;
    const Quality& q = r.quality;
    std::string manifold = Yes(q.manifold);
    if (!q.manifold) {
      manifold += " (";
      manifold += std::to_string(q.nonmanifold_edges);
      manifold += " non-manifold edges)";
    }
    std::fprintf(
        out,
        "| %s | %d | %zu | %zu | %.1f %% | %.3f | %s | %.2fM | %s | %.3f | %s | %.1f | %.1f | "
        "%zu / %zu | %s | %.2f | %.1f %% | %s |\n",
        c.name.c_str(), thr, q.vertices, q.faces,
        100.0 * (1.0 - double(q.vertices) / double(in.num_vertices())), r.best(), all.c_str(),
        nf / r.best() / 1e6, speedup.c_str(), b.cpu_seconds,
        c.kind == Kind::kMeshopt ? "–" : Fmt("%.3f", b.build_seconds).c_str(),
        double(b.total_bytes) / nf, double(b.work_bytes) / nf, qin.boundary_edges, q.boundary_edges,
        manifold.c_str(), q.min_angle_deg, 100 * q.frac_below_10, q.self_intersect.c_str());
  }
  std::fprintf(out, "\nPeers' targets: ");
  for (const Row& r : rows)
    if (r.config.kind == Kind::kOpenMesh)
      std::fprintf(out, "%s → %llu vertices; ", r.config.name.c_str(),
                   static_cast<unsigned long long>(r.config.target_vertices));
    else if (r.config.kind == Kind::kMeshopt)
      std::fprintf(out, "%s → %llu triangles; ", r.config.name.c_str(),
                   static_cast<unsigned long long>(r.config.target_faces));
  std::fprintf(out, "\n\nfemsimp passes and rejections (first repetition):\n\n");
  std::fprintf(out,
               "| run | thr | passes | stop | tried | removed | lock conflicts | inconsistent");
  for (int k = 0; k < static_cast<int>(femsimp::Reject::kCount); ++k)
    std::fprintf(out, " | %s", femsimp::RejectName(static_cast<femsimp::Reject>(k)));
  std::fprintf(out, " |\n|---|--:|--:|---|--:|--:|--:|--:");
  for (int k = 0; k < static_cast<int>(femsimp::Reject::kCount); ++k) std::fprintf(out, "|--:");
  std::fprintf(out, "|\n");
  for (const Row& r : rows) {
    if (!r.result) continue;
    uint64_t tried = 0, removed = 0, locks = 0, inc = 0;
    std::array<uint64_t, static_cast<int>(femsimp::Reject::kCount)> rej{};
    for (const auto& p : r.result->passes) {
      tried += p.tried, removed += p.removed, locks += p.lock_conflicts, inc += p.inconsistent;
      for (size_t k = 0; k < rej.size(); ++k) rej[k] += p.rejections[k];
    }
    std::fprintf(out, "| %s | %d | %zu | %s | %llu | %llu | %llu | %llu", r.config.name.c_str(),
                 r.config.options.threads, r.result->passes.size(),
                 femsimp::StopReasonName(r.result->stop_reason), (unsigned long long)tried,
                 (unsigned long long)removed, (unsigned long long)locks, (unsigned long long)inc);
    for (uint64_t v : rej) std::fprintf(out, " | %llu", (unsigned long long)v);
    std::fprintf(out, " |\n");
  }
  std::fprintf(out, "\n");
}

void WriteJson(const Args& a, const RawMesh& in, const std::vector<Row>& rows) {
  FILE* f = std::fopen(a.json.c_str(), "w");
  if (!f) return;
  std::fprintf(f, "{\"mesh\": \"%s\", \"input_vertices\": %zu, \"input_faces\": %zu, \"runs\": [",
               a.mesh.c_str(), in.num_vertices(), in.num_faces());
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const Sample& b = r.best_sample();
    const char* kind = r.config.kind == Kind::kFemsimp    ? "femsimp"
                       : r.config.kind == Kind::kOpenMesh ? "openmesh"
                                                          : "meshoptimizer";
    std::fprintf(f,
                 "%s\n  {\"name\": \"%s\", \"kind\": \"%s\", \"family\": \"%s\", \"threads\": %d, "
                 "\"best_seconds\": %.6f, \"seconds\": [",
                 i ? "," : "", r.config.name.c_str(), kind, r.config.family.c_str(),
                 r.config.kind == Kind::kFemsimp ? r.config.options.threads : 1, r.best());
    for (size_t k = 0; k < r.samples.size(); ++k)
      std::fprintf(f, "%s%.6f", k ? ", " : "", r.samples[k].seconds);
    const Quality& q = r.quality;
    std::fprintf(f,
                 "], \"cpu_seconds\": %.6f, \"build_seconds\": %.6f, \"engine_bytes\": %lld, "
                 "\"working_bytes\": %lld, "
                 "\"output_vertices\": %zu, \"output_faces\": %zu, \"boundary_edges\": %zu, "
                 "\"manifold\": %s, \"min_angle_deg\": %.4f, \"self_intersect\": \"%s\"",
                 b.cpu_seconds, b.build_seconds, (long long)b.total_bytes, (long long)b.work_bytes,
                 q.vertices, q.faces, q.boundary_edges, q.manifold ? "true" : "false",
                 q.min_angle_deg, q.self_intersect.c_str());
    if (r.result)
      std::fprintf(f, ", \"passes\": %zu, \"stop\": \"%s\", \"ratio\": %g", r.result->passes.size(),
                   femsimp::StopReasonName(r.result->stop_reason), r.config.options.ratio);
    std::fprintf(f, "}");
  }
  std::fprintf(f, "\n]}\n");
  std::fclose(f);
}

femsimp::flags::FlagSet Flags(Args* a) {
  using femsimp::flags::NumberKind;
  femsimp::flags::FlagSet set("femsimp_bench");
  set.String("--label", "TEXT", "name of the run in the report (default: the mesh)", &a->label);
  set.Number({.name = "--repeats",
              .metavar = "N",
              .help = "repetitions (the best counts)",
              .kind = NumberKind::kInteger,
              .range = femsimp::Range::Closed(1, 1000),
              .default_text = "3"},
             &a->repeats);
  set.Value("--threads", "1,2", "femsimp thread counts (default 1,2)",
            [a](const std::string& v) -> absl::Status {
              a->threads.clear();
              for (const std::string& t : femsimp::flags::SplitList(v)) {
                absl::StatusOr<double> n = femsimp::flags::ParseNumberIn(
                    "--threads", t, NumberKind::kInteger, femsimp::FindOption("threads")->range);
                if (!n.ok()) return n.status();
                a->threads.push_back(static_cast<int>(*n));
              }
              return absl::OkStatus();
            });
  set.Switch("--no-peers", "femsimp only, without OpenMesh and meshoptimizer",
             [a] { a->peers = false; });
  set.Choice("--variant", {{"auto"}, {"on"}, {"off"}},
             "the min-angle-0 variant: auto (when the paper's settings remove < 10 %), on, off",
             [a](size_t i) { a->variant = i == 0   ? "auto"
                                          : i == 1 ? "on"
                                                   : "off"; });
  set.Number({.name = "--si-timeout",
              .metavar = "SECONDS",
              .help = "time limit of each self-intersection check",
              .range = femsimp::Range::AtLeast(0),
              .unit = "seconds",
              .zero_means = "skip",
              .default_text = "60"},
             &a->si_limit_s);
  set.String("--json", "PATH", "also write the report as JSON", &a->json);
  femsimp::AddOptionFlag(set, "ratio", &a->target);
  set.Switch("--pass-log", "per-pass femsimp stats of the first repetition",
             [] { g_pass_log = true; });
  return set;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit =
          Flags(&a).ParseMain(argc, argv, "Usage: femsimp_bench MESH [flags]\n\n", "", &parsed))
    return *exit;
  if (parsed.positional.size() != 1) {
    std::fprintf(stderr, "femsimp_bench: needs exactly one MESH (see --help)\n");
    return femsimp::flags::kUsageExit;
  }
  a.mesh = parsed.positional[0];
  if (a.label.empty()) a.label = a.mesh;

  const auto t0 = Clock::now();
  auto loaded = femsimp::ReadMeshFile(a.mesh);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", std::string(loaded.status().message()).c_str());
    return 1;
  }
  const RawMesh& in = *loaded;
  const double load_s = Seconds(t0, Clock::now());
  std::fprintf(stderr, "loaded %s: %zu vertices, %zu faces in %.2f s\n", a.mesh.c_str(),
               in.num_vertices(), in.num_faces(), load_s);

  auto femsimp_row = [&](std::string name, std::string family, int threads, double min_angle,
                         bool topology) {
    Row r;
    if (family != "geo" && a.target.ratio > 0) {
      r.config.options.ratio = a.target.ratio;
      name += " → " + Fmt("%g", 100 * a.target.ratio) + " %";
    }
    r.config.name = std::move(name);
    r.config.family = std::move(family);
    r.config.options.threads = threads;
    r.config.options.min_angle_deg = min_angle;
    r.config.options.topology_only = topology;
    return r;
  };
  std::vector<Row> rows;
  // The first geometric 1-thread run fixes the peers' targets and whether the variant runs.
  for (int t : a.threads) rows.push_back(femsimp_row("femsimp geometric (paper)", "geo", t, 10, 0));
  std::sort(rows.begin(), rows.end(), [](const Row& x, const Row& y) {
    return x.config.options.threads < y.config.options.threads;
  });
  if (!Run(in, rows[0], true)) return 1;
  const uint64_t geo_v = rows[0].output.num_vertices(), geo_f = rows[0].output.num_faces();
  const double removed = 1.0 - double(geo_v) / double(in.num_vertices());
  std::fprintf(stderr, "paper settings removed %.2f %% of the vertices\n", 100 * removed);
  const bool variant = a.variant == "on" || (a.variant == "auto" && removed < 0.10);
  for (int t : a.threads) rows.push_back(femsimp_row("femsimp topology only", "topo", t, 10, 1));
  if (variant)
    for (int t : a.threads)
      rows.push_back(femsimp_row("femsimp geometric, min angle 0", "geo0", t, 0, 0));
  const size_t n_femsimp = rows.size();
  std::vector<Row> peer_rows;
  auto add_peers = [&](const char* tag, uint64_t v, uint64_t f) {
    Row om;
    om.config.kind = Kind::kOpenMesh;
    om.config.name = std::string("OpenMesh Decimater @ ") + tag;
    om.config.target_vertices = v;
    Row mo;
    mo.config.kind = Kind::kMeshopt;
    mo.config.name = std::string("meshoptimizer @ ") + tag;
    mo.config.target_faces = f;
    rows.push_back(om);
    rows.push_back(mo);
  };
  if (a.peers) {
    add_peers("paper's count", geo_v, geo_f);
    if (variant) {
      // The variant's 1-thread output fixes the second pair of peer targets.
      Row& v1 = rows[n_femsimp - a.threads.size()];
      if (!Run(in, v1, true)) return 1;
      add_peers("min-angle-0 count", v1.output.num_vertices(), v1.output.num_faces());
    }
  }

  for (int rep = 0; rep < a.repeats; ++rep) {
    std::fprintf(stderr, "repetition %d/%d\n", rep + 1, a.repeats);
    for (Row& r : rows) {
      const bool keep = r.samples.empty();
      if (rep == 0 && !keep) continue;  // already ran once to fix the targets
      if (!Run(in, r, keep)) return 1;
      std::fprintf(stderr, "  %-34s thr=%d %.3f s\n", r.config.name.c_str(),
                   r.config.options.threads, r.samples.back().seconds);
    }
  }
  std::fprintf(stderr, "checking quality\n");
  Quality qin = Analyze(in, a.si_limit_s);
  for (Row& r : rows) r.quality = Analyze(r.output, a.si_limit_s);
  PrintReport(a, in, qin, load_s, rows, stdout);
  if (!a.json.empty()) WriteJson(a, in, rows);
  return 0;
}
