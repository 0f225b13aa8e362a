// What the scan for crossing faces costs on one thread and on THREADS: the repair's scan of every
// input (crossings only, every pair listed) and the output's check (crossings, overlaps and folds
// counted), interleaved per repeat so that machine noise hits every variant alike. Prints a
// markdown table, best seconds and the speedup, and fails where the threads' result differs from
// one thread's (counts, first pairs, lists).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bench/mesh_args.h"
#include "engine/crossings.h"
#include "engine/io/mesh_io.h"
#include "engine/option_table.h"
#include "engine/worker_pool.h"

namespace {

struct Run {
  femsimp::SoupCrossings found;
  femsimp::CrossingPairLists lists;
};

bool Same(const Run& a, const Run& b) {
  const femsimp::SoupCrossings &x = a.found, &y = b.found;
  return x.pairs == y.pairs && x.face_a == y.face_a && x.face_b == y.face_b && x.at == y.at &&
         x.cut_short == y.cut_short && x.overlaps.pairs == y.overlaps.pairs &&
         x.overlaps.area == y.overlaps.area && x.folds.pairs == y.folds.pairs &&
         a.lists.crossing == b.lists.crossing && a.lists.overlapping == b.lists.overlapping &&
         a.lists.folded == b.lists.folded;
}

}  // namespace

// MESH [REPEATS [THREADS]]
int main(int argc, char** argv) {
  using femsimp::flags::NumberKind;
  std::vector<femsimp::bench::PositionalNumber> numbers = {
      {"REPEATS", 3, NumberKind::kInteger, femsimp::Range::Closed(1, 1000)},
      {"THREADS", 2, NumberKind::kInteger, femsimp::FindOption("threads")->range}};
  std::string mesh;
  if (std::optional<int> exit =
          femsimp::bench::ParseMeshAndNumbers(argc, argv, "crossings_cost", numbers, &mesh))
    return *exit;
  const int repeats = static_cast<int>(numbers[0].value);
  const int threads = static_cast<int>(numbers[1].value);
  absl::StatusOr<femsimp::RawMesh> soup = femsimp::ReadMeshFile(mesh);
  if (!soup.ok()) {
    std::fprintf(stderr, "%s\n", std::string(soup.status().message()).c_str());
    return 1;
  }
  femsimp::WorkerPool pool(threads);
  struct Variant {
    const char* scan;
    bool repair;  // the repair's scan (crossings only, listed), else the output's check
    int threads;
    std::vector<double> seconds;
    Run last;
  };
  std::vector<Variant> variants;
  for (bool repair : {true, false})
    for (int t : {1, threads})
      variants.push_back({repair ? "repair's scan" : "output's check", repair, t, {}, {}});
  for (int r = 0; r < repeats; ++r)
    for (Variant& v : variants) {
      Run run;
      const auto start = std::chrono::steady_clock::now();
      run.found = femsimp::FindCrossings(*soup, {.lists = v.repair ? &run.lists : nullptr,
                                                 .crossings_only = v.repair,
                                                 .pool = v.threads > 1 ? &pool : nullptr});
      v.seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      v.last = std::move(run);
    }
  std::printf("%s: %zu faces, best of %d\n\n", mesh.c_str(), soup->num_faces(), repeats);
  std::printf("| scan | threads | seconds | speedup | crossing pairs | same as 1 thread |\n");
  std::printf("|---|---:|---:|---:|---:|---|\n");
  bool all_same = true;
  for (size_t i = 0; i < variants.size(); ++i) {
    const Variant& v = variants[i];
    const Variant& one = variants[i - i % 2];
    const double best = *std::min_element(v.seconds.begin(), v.seconds.end());
    const double best_one = *std::min_element(one.seconds.begin(), one.seconds.end());
    const bool same = Same(v.last, one.last);
    all_same = all_same && same;
    std::printf("| %s | %d | %.3f | %.2f | %llu%s | %s |\n", v.scan, v.threads, best,
                best_one / best, static_cast<unsigned long long>(v.last.found.pairs),
                v.last.found.cut_short ? "+" : "", same ? "yes" : "NO");
  }
  return all_same ? 0 : 1;
}
