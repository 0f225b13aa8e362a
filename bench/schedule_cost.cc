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

#include "bench/mesh_args.h"
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
  std::vector<femsimp::bench::PositionalNumber> numbers = {
      {"REPEATS", 3, NumberKind::kInteger, femsimp::Range::Closed(1, 1000)},
      {"THREADS", 2, NumberKind::kInteger, femsimp::FindOption("threads")->range}};
  std::string mesh;
  if (std::optional<int> exit =
          femsimp::bench::ParseMeshAndNumbers(argc, argv, "schedule_cost", numbers, &mesh))
    return *exit;
  const int repeats = static_cast<int>(numbers[0].value);
  const int threads = static_cast<int>(numbers[1].value);
  absl::StatusOr<femsimp::RawMesh> raw = femsimp::ReadMeshFile(mesh);
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
              mesh.c_str(), raw->num_vertices(), repeats);
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
