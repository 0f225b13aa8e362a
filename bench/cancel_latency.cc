// How soon a cancel ends a running job, wherever it lands: set-up (features, face index,
// mass), a pass's cost-and-sort phase, its rounds, its bookkeeping. Runs the service's cancel
// test's long job (target 50 vertices, 1 % tolerance, 1 % volume bound) once per cancel time
// and prints the latency from the cancel to Simplify's return. The service promises 0.5 s
// (tests/service/cancel_test.cc); this shows the engine's share of it on a given machine.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/simplify.h"

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

// MESH [BACKEND=native|cell]
int main(int argc, char** argv) {
  femsimp::flags::FlagSet flags("cancel_latency");
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit =
          flags.ParseMain(argc, argv, "Usage: cancel_latency MESH [native|cell]\n\n", "", &parsed))
    return *exit;
  const std::vector<std::string>& args = parsed.positional;
  if (args.empty() || args.size() > 2 ||
      (args.size() == 2 && args[1] != "native" && args[1] != "cell")) {
    std::fprintf(stderr, "cancel_latency: needs MESH and at most a back end (see --help)\n");
    return femsimp::flags::kUsageExit;
  }
  const bool cell = args.size() == 2 && args[1] == "cell";
  absl::StatusOr<femsimp::RawMesh> raw = femsimp::ReadMeshFile(args[0]);
  if (!raw.ok()) {
    std::fprintf(stderr, "%s\n", std::string(raw.status().message()).c_str());
    return 1;
  }
  femsimp::SimplifyOptions o;
  o.threads = 1;
  o.target_vertices = 50;
  if (cell) {
    o.backend = femsimp::Backend::kCell;
    o.cell.spes = 1;
  } else {
    o.tolerance_relative = 0.01;
    o.max_volume_change = 0.01;
  }
  std::printf("%s: %zu vertices, %s back end, one context\n\n", args[0].c_str(),
              raw->num_vertices(), cell ? "cell" : "native");
  std::printf("| cancel at s | passes done | latency s |\n|--:|--:|--:|\n");
  double worst = 0.0;
  for (double at : {0.02, 0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 1.3, 1.6, 2.0, 2.5, 3.0}) {
    absl::StatusOr<femsimp::Mesh> mesh = femsimp::Mesh::Build(*raw);
    if (!mesh.ok()) {
      std::fprintf(stderr, "%s\n", std::string(mesh.status().message()).c_str());
      return 1;
    }
    std::atomic<bool> cancel{false};
    std::atomic<int> passes{0};
    femsimp::SimplifyControl control;
    control.cancelled = [&] { return cancel.load(std::memory_order_relaxed); };
    control.on_pass = [&](const femsimp::PassStats&) { passes.fetch_add(1); };
    Clock::time_point cancelled_at;
    const Clock::time_point start = Clock::now();
    std::thread canceller([&] {
      std::this_thread::sleep_until(start + std::chrono::duration<double>(at));
      cancelled_at = Clock::now();
      cancel.store(true);
    });
    absl::StatusOr<femsimp::SimplifyResult> result = femsimp::Simplify(*mesh, o, control);
    const Clock::time_point returned = Clock::now();
    canceller.join();
    if (!result.ok()) {
      std::fprintf(stderr, "%s\n", std::string(result.status().message()).c_str());
      return 1;
    }
    if (result->stop_reason != femsimp::StopReason::kCancelled) {
      std::printf("| %.2f | %d | (finished first) |\n", at, passes.load());
      continue;
    }
    const double latency = Seconds(returned - cancelled_at);
    worst = std::max(worst, latency);
    std::printf("| %.2f | %d | %.3f |\n", at, passes.load(), latency);
  }
  std::printf("\nworst latency: %.3f s\n", worst);
  return 0;
}
