// One side-by-side speed table (issue 14, item 5): femsimp with its defaults and with the paper's
// kernel alone, at 1 and 2 threads, beside meshoptimizer and OpenMesh's Decimater, on the same
// loaded meshes; every run best of N interleaved repetitions. Prints markdown: the table, the
// machine, the command, and the targets as measured ratios.
//
// femsimp is prepared with PrepareMesh (repair, spatial renumbering, build), as the CLI and the
// server prepare it, so the table measures what users get. Peak heap: bench/heap_counter.h,
// beyond the loaded soup.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "bench/heap_counter.h"
#include "bench/peers/peer_run.h"
#include "bench/speed_peers.h"
#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/option_flags.h"
#include "engine/prepare.h"
#include "engine/simplify.h"

namespace {

using femsimp::RawMesh;
using femsimp::bench::SpeedSample;
using Clock = std::chrono::steady_clock;

enum class System { kFemsimpFe, kFemsimpPaper, kMeshopt, kOpenMesh };

const char* SystemName(System s) {
  switch (s) {
    case System::kFemsimpFe:
      return "femsimp defaults (fe)";
    case System::kFemsimpPaper:
      return "femsimp --preset paper --min-angle 0";
    case System::kMeshopt:
      return "meshoptimizer meshopt_simplify";
    case System::kOpenMesh:
      return "OpenMesh Decimater";
  }
  return "?";
}

bool IsFemsimp(System s) { return s == System::kFemsimpFe || s == System::kFemsimpPaper; }

struct Row {
  System system = System::kFemsimpFe;
  int threads = 1;
  femsimp::SimplifyOptions options;  // femsimp only
  uint64_t target = 0;               // OpenMesh: vertices; meshoptimizer: faces
  std::vector<SpeedSample> samples;
  uint64_t output_vertices = 0, output_faces = 0;  // of the first repetition
  std::optional<femsimp::SimplifyResult> result;   // femsimp, first repetition
  std::string skipped;                             // why it did not run (empty: it ran)

  const SpeedSample& best() const {
    return *std::min_element(
        samples.begin(), samples.end(),
        [](const SpeedSample& a, const SpeedSample& b) { return a.seconds < b.seconds; });
  }
};

struct MeshRows {
  std::string name, path;
  uint64_t vertices = 0, faces = 0;
  double ratio = 0;
  std::vector<Row> rows;

  const Row* Find(System s, int threads) const {
    for (const Row& r : rows)
      if (r.system == s && r.threads == threads && r.skipped.empty() && !r.samples.empty())
        return &r;
    return nullptr;
  }
};

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// One femsimp run as the CLI makes it: PrepareMesh on a copy of the soup, then Simplify. The
// copy is made before the heap baseline, as the CLI hands its freshly read soup to PrepareMesh.
absl::StatusOr<SpeedSample> RunFemsimp(const RawMesh& in, Row& row, bool keep) {
  RawMesh copy = in;
  const int64_t live0 = femsimp::bench::LiveHeapBytes();
  femsimp::bench::ResetHeapPeak();
  SpeedSample s;
  const auto t0 = Clock::now();
  absl::StatusOr<femsimp::PreparedMesh> prepared =
      femsimp::PrepareMesh(std::move(copy), row.options.repair);
  s.build_seconds = Seconds(t0, Clock::now());
  if (!prepared.ok()) return prepared.status();
  const int64_t build_peak = femsimp::bench::PeakHeapBytes();
  const int64_t live1 = femsimp::bench::LiveHeapBytes();
  femsimp::bench::ResetHeapPeak();
  const double cpu0 = femsimp::bench::ProcessCpuSeconds();
  absl::StatusOr<femsimp::SimplifyResult> result = femsimp::Simplify(prepared->mesh, row.options);
  s.cpu_seconds = femsimp::bench::ProcessCpuSeconds() - cpu0;
  if (!result.ok()) return result.status();
  const int64_t simp_peak = femsimp::bench::PeakHeapBytes();
  s.seconds = result->engine_seconds;
  s.work_bytes = simp_peak - live1;
  s.total_bytes = std::max(build_peak, simp_peak) - live0;
  if (keep) {
    row.output_vertices = result->output_vertices;
    row.output_faces = result->output_faces;
    row.result = *std::move(result);
  }
  return s;
}

absl::Status Run(const RawMesh& in, Row& row, bool keep) {
  SpeedSample s;
  RawMesh out;
  switch (row.system) {
    case System::kFemsimpFe:
    case System::kFemsimpPaper: {
      absl::StatusOr<SpeedSample> f = RunFemsimp(in, row, keep);
      if (!f.ok()) return f.status();
      s = *f;
      break;
    }
    case System::kMeshopt:
      s = femsimp::bench::RunMeshoptSimplify(in, row.target, keep ? &out : nullptr);
      break;
    case System::kOpenMesh:
      s = femsimp::bench::RunOpenMeshDecimater(in, row.target, keep ? &out : nullptr);
      break;
  }
  if (keep && !IsFemsimp(row.system)) {
    row.output_vertices = out.num_vertices();
    row.output_faces = out.num_faces();
  }
  row.samples.push_back(s);
  return absl::OkStatus();
}

struct Args {
  std::vector<std::string> meshes;  // NAME=PATH or PATH (name: the file's stem)
  int repeats = 3;
  bool openmesh_all = false;
  double openmesh_max_faces = 1.2e6;
  std::string blade3 = "blade_loop3", blade4 = "blade_loop4";
  std::string command;  // the command that made the table (default: this program's)
  femsimp::SimplifyOptions target;
};

std::string Fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

uint64_t TargetVertices(const MeshRows& m) {
  return static_cast<uint64_t>(std::llround(m.ratio * static_cast<double>(m.vertices)));
}

// Whether femsimp reached the target within 10 %, and if not why it stopped.
std::string StopText(const MeshRows& m, const Row& r) {
  const femsimp::SimplifyResult& res = *r.result;
  const uint64_t target = TargetVertices(m);
  const bool reached =
      static_cast<double>(res.output_vertices) <= 1.1 * static_cast<double>(target);
  std::string text = "target " + std::to_string(target) + " V ";
  text += reached ? "reached" : "not reached";
  text += "; stop ";
  text += femsimp::StopReasonName(res.stop_reason);
  if (res.limiting_rule != femsimp::Reject::kCount) {
    text += ", limit ";
    text += femsimp::RejectName(res.limiting_rule);
  }
  return text;
}

bool ReachedTarget(const MeshRows& m, const Row& r) {
  return static_cast<double>(r.output_vertices) <= 1.1 * static_cast<double>(TargetVertices(m));
}

absl::StatusOr<MeshRows> RunMesh(const Args& a, const std::string& spec) {
  MeshRows m;
  const size_t eq = spec.find('=');
  m.path = eq == std::string::npos ? spec : spec.substr(eq + 1);
  if (eq != std::string::npos) {
    m.name = spec.substr(0, eq);
  } else {
    const size_t slash = m.path.find_last_of('/');
    m.name = m.path.substr(slash == std::string::npos ? 0 : slash + 1);
    m.name = m.name.substr(0, m.name.find('.'));
  }
  absl::StatusOr<RawMesh> loaded = femsimp::ReadMeshFile(m.path);
  if (!loaded.ok()) return loaded.status();  // the reader's message names the file
  const RawMesh& in = *loaded;
  m.vertices = in.num_vertices();
  m.faces = in.num_faces();
  m.ratio = a.target.ratio;
  std::fprintf(stderr, "%s: %llu vertices, %llu faces\n", m.name.c_str(),
               static_cast<unsigned long long>(m.vertices),
               static_cast<unsigned long long>(m.faces));

  for (System s : {System::kFemsimpFe, System::kFemsimpPaper})
    for (int t : {1, 2}) {
      Row r;
      r.system = s;
      r.threads = t;
      r.options = femsimp::PresetOptions(s == System::kFemsimpFe ? femsimp::Preset::kFe
                                                                 : femsimp::Preset::kPaper);
      if (s == System::kFemsimpPaper) r.options.min_angle_deg = 0;
      r.options.ratio = a.target.ratio;
      r.options.threads = t;
      m.rows.push_back(r);
    }
  // The defaults' 1-thread output fixes the peers' targets.
  if (absl::Status st = Run(in, m.rows[0], true); !st.ok())
    return absl::Status(st.code(), m.name + ": " + std::string(st.message()));
  Row mo;
  mo.system = System::kMeshopt;
  mo.target = m.rows[0].output_faces;
  m.rows.push_back(mo);
  Row om;
  om.system = System::kOpenMesh;
  om.target = m.rows[0].output_vertices;
  if (!a.openmesh_all && static_cast<double>(m.faces) > a.openmesh_max_faces)
    om.skipped = "skipped: " + std::to_string(m.faces) + " faces > " +
                 Fmt("%.0f", a.openmesh_max_faces) + " (minutes; --openmesh-all runs it)";
  m.rows.push_back(om);

  for (int rep = 0; rep < a.repeats; ++rep) {
    std::fprintf(stderr, "  repetition %d/%d\n", rep + 1, a.repeats);
    for (Row& r : m.rows) {
      if (!r.skipped.empty()) continue;
      const bool keep = r.samples.empty();
      if (rep == 0 && !keep) continue;  // ran once already, to fix the peers' targets
      if (absl::Status st = Run(in, r, keep); !st.ok())
        return absl::Status(
            st.code(), m.name + ", " + SystemName(r.system) + ": " + std::string(st.message()));
      std::fprintf(stderr, "    %-40s thr=%d %.3f s\n", SystemName(r.system), r.threads,
                   r.samples.back().seconds);
    }
  }
  return m;
}

std::string LoadAverage() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

std::string CpuModel() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

void PrintTable(const std::vector<MeshRows>& meshes) {
  std::printf(
      "| mesh | system | threads | output V | engine s (best) | × meshoptimizer | 2-thread "
      "speedup | build s | peak heap MiB | femsimp stop |\n");
  std::printf("|---|---|--:|--:|--:|--:|--:|--:|--:|---|\n");
  for (const MeshRows& m : meshes) {
    const Row* mo = m.Find(System::kMeshopt, 1);
    for (const Row& r : m.rows) {
      const std::string mesh =
          m.name + " (" + std::to_string(m.vertices) + " V, " + std::to_string(m.faces) + " F)";
      if (!r.skipped.empty()) {
        std::printf("| %s | %s | 1 | – | – | – | – | – | – | %s |\n", mesh.c_str(),
                    SystemName(r.system), r.skipped.c_str());
        continue;
      }
      const SpeedSample& b = r.best();
      std::string speedup = "–";
      if (IsFemsimp(r.system) && r.threads == 2)
        if (const Row* one = m.Find(r.system, 1))
          speedup = Fmt("%.2f×", one->best().seconds / b.seconds);
      std::printf("| %s | %s | %d | %llu | %.3f | %s | %s | %s | %.1f | %s |\n", mesh.c_str(),
                  SystemName(r.system), r.threads,
                  static_cast<unsigned long long>(r.output_vertices), b.seconds,
                  mo ? Fmt("%.2f", b.seconds / mo->best().seconds).c_str() : "–", speedup.c_str(),
                  r.system == System::kMeshopt ? "–" : Fmt("%.3f", b.build_seconds).c_str(),
                  static_cast<double>(b.total_bytes) / (1024.0 * 1024.0),
                  r.result ? StopText(m, r).c_str() : "");
    }
  }
}

const MeshRows* FindMesh(const std::vector<MeshRows>& meshes, const std::string& name) {
  for (const MeshRows& m : meshes)
    if (m.name == name) return &m;
  return nullptr;
}

std::string Verdict(bool met) { return met ? "**met**" : "**not met**"; }

// The targets, each from this run's rows.
void PrintTargets(const Args& a, const std::vector<MeshRows>& meshes) {
  std::printf("\nIssue 14's targets, measured in this run (femsimp at its defaults):\n\n");
  const MeshRows* b3 = FindMesh(meshes, a.blade3);
  const MeshRows* b4 = FindMesh(meshes, a.blade4);
  const Row* fe1 = b3 ? b3->Find(System::kFemsimpFe, 1) : nullptr;
  const Row* fe2 = b3 ? b3->Find(System::kFemsimpFe, 2) : nullptr;
  const Row* mo = b3 ? b3->Find(System::kMeshopt, 1) : nullptr;
  if (!fe1 || !fe2 || !mo) {
    std::printf("- %s not in this run: the blade targets are not measured.\n", a.blade3.c_str());
    return;
  }
  const bool reached = ReachedTarget(*b3, *fe2);
  const double r_mo = fe2->best().seconds / mo->best().seconds;
  std::printf(
      "- %s, 2 threads ≤ 0.5 × meshoptimizer (1 thread), reaching 10 %% within 10 %%: %.2f × "
      "(%.3f s / %.3f s), target %s → %s\n",
      a.blade3.c_str(), r_mo, fe2->best().seconds, mo->best().seconds,
      reached ? "reached" : "not reached", Verdict(reached && r_mo <= 0.5).c_str());
  const double speedup = fe1->best().seconds / fe2->best().seconds;
  std::printf("- %s, 2 threads ≥ 1.8 × faster than 1: %.2f × → %s\n", a.blade3.c_str(), speedup,
              Verdict(speedup >= 1.8).c_str());
  const Row* fe4_1 = b4 ? b4->Find(System::kFemsimpFe, 1) : nullptr;
  const Row* fe4_2 = b4 ? b4->Find(System::kFemsimpFe, 2) : nullptr;
  if (!fe4_1 || !fe4_2) {
    std::printf("- %s not in this run: the linear-growth target is not measured.\n",
                a.blade4.c_str());
    return;
  }
  const double g1 = fe4_1->best().seconds / fe1->best().seconds;
  const double g2 = fe4_2->best().seconds / fe2->best().seconds;
  // Two runs that stopped short of the target did different shares of the job: their time
  // ratio says nothing about how the cost grows.
  const bool both_reached = reached && ReachedTarget(*b4, *fe4_2) && ReachedTarget(*b3, *fe1) &&
                            ReachedTarget(*b4, *fe4_1);
  std::printf(
      "- %s time ≤ 4.4 × %s time (%.2f × the faces), both reaching 10 %%: %.2f × at 1 thread, "
      "%.2f × at 2 threads, %s → %s\n",
      a.blade4.c_str(), a.blade3.c_str(),
      static_cast<double>(b4->faces) / static_cast<double>(b3->faces), g1, g2,
      both_reached ? "targets reached" : "a target not reached (the ratio compares unequal jobs)",
      Verdict(both_reached && g1 <= 4.4 && g2 <= 4.4).c_str());
}

femsimp::flags::FlagSet Flags(Args* a) {
  using femsimp::flags::NumberKind;
  femsimp::flags::FlagSet set("speed_table");
  set.Number({.name = "--repeats",
              .metavar = "N",
              .help = "interleaved repetitions of every run (the best counts)",
              .kind = NumberKind::kInteger,
              .range = femsimp::Range::Closed(1, 1000),
              .default_text = "3"},
             &a->repeats);
  set.Switch("--openmesh-all", "run OpenMesh on every mesh, also those above --openmesh-max-faces",
             [a] { a->openmesh_all = true; });
  set.Number({.name = "--openmesh-max-faces",
              .metavar = "N",
              .help = "OpenMesh is skipped, with a note, on meshes with more faces",
              .kind = NumberKind::kInteger,
              .range = femsimp::Range::AtLeast(1),
              .default_text = "1200000"},
             &a->openmesh_max_faces);
  set.String("--blade3", "NAME", "mesh of the speed targets (default blade_loop3)", &a->blade3);
  set.String("--blade4", "NAME", "mesh of the linear-growth target (default blade_loop4)",
             &a->blade4);
  set.String("--command", "TEXT", "the command printed below the table (default: this one)",
             &a->command);
  femsimp::AddOptionFlag(set, "ratio", &a->target, "0.1");
  return set;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  a.target.ratio = 0.1;
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit = Flags(&a).ParseMain(
          argc, argv, "Usage: speed_table [NAME=]MESH... [flags]\n\n", "", &parsed))
    return *exit;
  a.meshes = parsed.positional;
  if (a.meshes.empty()) {
    std::fprintf(stderr, "speed_table: needs at least one MESH (see --help)\n");
    return femsimp::flags::kUsageExit;
  }
  if (a.target.ratio <= 0) {
    std::fprintf(stderr, "speed_table: --ratio 0 is refused: the table compares at a target\n");
    return femsimp::flags::kUsageExit;
  }
  if (a.command.empty())
    for (int i = 0; i < argc; ++i) {
      if (i) a.command += ' ';
      a.command += argv[i];
    }

  const std::string load_before = LoadAverage();
  std::vector<MeshRows> meshes;
  for (const std::string& spec : a.meshes) {
    absl::StatusOr<MeshRows> m = RunMesh(a, spec);
    if (!m.ok()) {
      std::fprintf(stderr, "speed_table: %s\n", std::string(m.status().message()).c_str());
      return 1;
    }
    meshes.push_back(*std::move(m));
  }
  const std::string load_after = LoadAverage();

  // Prose wrapped at 100 columns, as docs/BENCHMARKS.md is.
  std::printf(
      "Every mesh loaded once; femsimp and the peers start from the same soup. femsimp to %g %% "
      "of the\nvertices; meshoptimizer (LockBorder) to the face count, OpenMesh (quadric + "
      "normal flipping + aspect\nratio) to the vertex count of femsimp's defaults' 1-thread "
      "output. Best of %d interleaved\nrepetitions. Engine s: the simplification alone; build s: "
      "PrepareMesh (repair, spatial\nrenumbering, build) or the TriMesh construction; peak heap: "
      "beyond the loaded soup, over build and\nsimplification; × meshoptimizer: engine time over "
      "meshoptimizer's on the same mesh.\n\n",
      100 * a.target.ratio, a.repeats);
  PrintTable(meshes);
  PrintTargets(a, meshes);
  std::printf(
      "\nMachine: %ld cores (nproc), %s; load average (1, 5, 15 min) %s before, %s after.\n",
      sysconf(_SC_NPROCESSORS_ONLN), CpuModel().c_str(), load_before.c_str(), load_after.c_str());
  std::printf("\nCommand:\n\n```sh\n%s\n```\n", a.command.c_str());
  return 0;
}
