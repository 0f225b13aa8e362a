// What deterministic output costs: engine time of a plain call (the fe preset) in the default
// deterministic schedule against the same call with --schedule free, at 1 and at THREADS
// threads, interleaved per repeat so that machine noise hits every variant alike. Prints a
// markdown table: the deterministic time over the free time at each thread count (issue 12
// asks for at most 1.15 at the parallel count) and whether the deterministic outputs agree.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/option_table.h"
#include "engine/simplify.h"

namespace {

struct Variant {
  std::string name;
  femsimp::SimplifyOptions options;
  std::vector<double> seconds;
  uint64_t vertices = 0;
  std::vector<float> output;  // positions, to compare the deterministic runs
};

double Best(std::vector<double> v) { return *std::min_element(v.begin(), v.end()); }

}  // namespace

// MESH [REPEATS [THREADS]]
int main(int argc, char** argv) {
  using femsimp::flags::NumberKind;
  femsimp::flags::FlagSet flags("schedule_cost");
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit = flags.ParseMain(
          argc, argv, "Usage: schedule_cost MESH [REPEATS=3] [THREADS=2]\n\n", "", &parsed))
    return *exit;
  const std::vector<std::string>& args = parsed.positional;
  if (args.empty() || args.size() > 3) {
    std::fprintf(stderr, "schedule_cost: needs MESH and at most two numbers (see --help)\n");
    return femsimp::flags::kUsageExit;
  }
  int numbers[2] = {3, 2};
  const femsimp::Range ranges[2] = {femsimp::Range::Closed(1, 1000),
                                    femsimp::FindOption("threads")->range};
  const char* names[2] = {"REPEATS", "THREADS"};
  for (size_t i = 1; i < args.size(); ++i) {
    absl::StatusOr<double> v =
        femsimp::flags::ParseNumberIn(names[i - 1], args[i], NumberKind::kInteger, ranges[i - 1]);
    if (!v.ok()) {
      std::fprintf(stderr, "schedule_cost: %s\n", std::string(v.status().message()).c_str());
      return femsimp::flags::kUsageExit;
    }
    numbers[i - 1] = static_cast<int>(*v);
  }
  const int repeats = numbers[0], threads = numbers[1];
  absl::StatusOr<femsimp::RawMesh> raw = femsimp::ReadMeshFile(args[0]);
  if (!raw.ok()) {
    std::fprintf(stderr, "%s\n", std::string(raw.status().message()).c_str());
    return 1;
  }
  std::vector<Variant> variants;
  for (int t : {1, threads})
    for (femsimp::Schedule s : {femsimp::Schedule::kFree, femsimp::Schedule::kDeterministic}) {
      femsimp::SimplifyOptions o;  // the fe preset: a plain call
      o.threads = t;
      o.schedule = s;
      variants.push_back({std::string(s == femsimp::Schedule::kFree ? "free" : "deterministic") +
                              ", " + std::to_string(t) + " thread" + (t > 1 ? "s" : ""),
                          o,
                          {},
                          0,
                          {}});
    }
  for (int r = 0; r < repeats; ++r)
    for (Variant& v : variants) {
      absl::StatusOr<femsimp::Mesh> mesh = femsimp::Mesh::Build(*raw);
      if (!mesh.ok()) {
        std::fprintf(stderr, "%s\n", std::string(mesh.status().message()).c_str());
        return 1;
      }
      absl::StatusOr<femsimp::SimplifyResult> result = femsimp::Simplify(*mesh, v.options);
      if (!result.ok()) {
        std::fprintf(stderr, "%s: %s\n", v.name.c_str(),
                     std::string(result.status().message()).c_str());
        return 1;
      }
      v.seconds.push_back(result->engine_seconds);
      v.vertices = result->output_vertices;
      v.output = mesh->ToRaw().positions;
    }
  std::printf("%s: %zu vertices, a plain call (fe preset), best of %d interleaved repeats\n\n",
              args[0].c_str(), raw->num_vertices(), repeats);
  std::printf(
      "| schedule, threads | vertices out | engine s (best) | vs free at the same threads "
      "| speedup over 1 thread |\n|---|--:|--:|--:|--:|\n");
  for (size_t i = 0; i < variants.size(); ++i) {
    const Variant& v = variants[i];
    const double free_same = Best(variants[i & ~size_t{1}].seconds);
    const double one = Best(variants[i & size_t{1}].seconds);
    std::printf("| %s | %llu | %.3f | %.2fx | %.2f |\n", v.name.c_str(),
                static_cast<unsigned long long>(v.vertices), Best(v.seconds),
                Best(v.seconds) / free_same, one / Best(v.seconds));
  }
  const bool same = variants[1].output == variants[3].output;
  std::printf("\nDeterministic outputs at 1 and %d threads: %s\n", threads,
              same ? "identical" : "DIFFERENT");
  return same ? 0 : 1;
}
