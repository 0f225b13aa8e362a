// The cell back end: the removal kernel on N emulated SPEs (cellsim), one kernel per software
// thread, each SPE visiting its share of the candidates in cost order.
#include <chrono>
#include <cmath>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/cell_port.h"
#include "engine/removal_backend.h"

namespace femsimp {
namespace {

// Modeled cycles of the work done outside the SPE kernel (documented in docs/CELLSIM.md):
// the cost of one vertex (one-ring walk and angle sum, parallel over the SPEs as in the paper)
// and one comparison-and-move of the PPE's sequential sort.
constexpr uint64_t kCostCyclesPerVertex = 400;
constexpr uint64_t kSortCyclesPerElementLevel = 8;
// Deterministic rounds (engine/rounds.h): each candidate's fan box (its one-ring walk, as for
// the cost) is one more SPE run, parallel over the SPEs; choosing the winners (a sort of the
// boxes and a sweep) is PPE work, like the pass's sort.
constexpr uint64_t kFanBoxCyclesPerCandidate = 400;
constexpr size_t kSoftwareThreadStack = 48 * 1024;

CellPassCounters ToPassCounters(const cellsim::SpeCounters& c) {
  CellPassCounters p;
  p.cache_hits = c.cache_hits;
  p.cache_misses = c.cache_misses;
  p.stale_detected = c.stale_detections;
  p.dma_transfers = c.dma_gets + c.dma_puts;
  p.dma_bytes = c.dma_get_bytes + c.dma_put_bytes;
  p.atomic_ops = c.atomic_getllar + c.atomic_putllc_success + c.atomic_putllc_failure +
                 c.atomic_putlluc + c.atomic_loads;
  p.thread_switches = c.thread_switches;
  p.busy_cycles = c.BusyCycles();
  p.modeled_cycles = c.ModeledCycles();
  return p;
}

class CellBackend final : public RemovalBackend {
 public:
  CellBackend(Mesh& mesh, const KernelConfig& kernel, const CellOptions& options,
              std::unique_ptr<cellsim::Runtime> runtime)
      : mesh_(mesh), kernel_(kernel), options_(options), runtime_(std::move(runtime)) {}

  int contexts() const override { return runtime_->num_spes(); }

  absl::Status RunRemoval(const RemovalPhase& phase, PassStats& stats) override {
    const int n = runtime_->num_spes();
    runtime_->ResetCounters();
    uint64_t sort_cycles = 0, cost_cycles = 0, claim_cycles = 0;
    if (phase.pass_start) {
      // PPE: the sequential sort of the removable vertices.
      const double sorted = static_cast<double>(phase.sorted);
      sort_cycles = static_cast<uint64_t>(sorted * std::max(1.0, std::log2(std::max(2.0, sorted))) *
                                          kSortCyclesPerElementLevel);
      // SPEs: the cost of every vertex, split evenly.
      cost_cycles = kCostCyclesPerVertex * mesh_.vertex_capacity() / n;
    }
    if (phase.claimed > 0) {
      const double claimed = static_cast<double>(phase.claimed);
      claim_cycles = kFanBoxCyclesPerCandidate * phase.claimed / n +
                     cellsim::CostModel{}.spe_run_overhead_cycles;
      sort_cycles += static_cast<uint64_t>(
          claimed * std::max(1.0, std::log2(std::max(2.0, claimed))) * kSortCyclesPerElementLevel);
    }

    std::vector<std::vector<uint32_t>> lists(n);
    for (size_t i = 0; i < phase.count; ++i)
      lists[phase.blocks ? i * n / phase.count : i % n].push_back(phase.candidates[i]);
    std::vector<std::span<const uint32_t>> spans(lists.begin(), lists.end());
    std::vector<KernelStats> per_spe(n);
    const auto start = std::chrono::steady_clock::now();
    absl::Status status = runtime_->Run(
        [&](cellsim::SpeContext& spe) {
          KernelStats& kstats = per_spe[spe.index()];
          if (phase.fresh_caches) spe.cache().InvalidateAll();
          absl::Status s = spe.RunThreads(options_.spe_threads, [&](cellsim::SpeContext& ctx, int) {
            // The port and the kernel (rings, geometry, put buffers) live on this software
            // thread's stack, i.e. in the local store.
            CellPort port(ctx, mesh_);
            port.set_reread_on_stale(options_.reread_on_stale);
            RemovalKernel<CellPort> kernel(port, *kernel_.rules, kernel_.quadric, *phase.budget,
                                           kstats, kernel_.placement);
            RunCandidates(kernel, phase, [&ctx]() -> std::optional<uint32_t> {
              const std::optional<uint64_t> v = ctx.NextWorkItem();
              if (!v) return std::nullopt;
              return static_cast<uint32_t>(*v);
            });
          });
          if (!s.ok()) spe.ReportError(s);
        },
        cellsim::WorkPlan::PerSpe(std::move(spans)));
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!status.ok()) return status;

    // A pass may run as several phases (deterministic rounds): the counters add up.
    if (!stats.cell) stats.cell.emplace();
    stats.cell_per_spe.resize(n);
    for (int i = 0; i < n; ++i) {
      AddKernelStats(per_spe[i], stats);
      CellPassCounters p = ToPassCounters(runtime_->spe(i).counters());
      p.stale_reread = per_spe[i].stale_reread;
      p.stale_skipped = per_spe[i].inconsistent;
      *stats.cell += p;
      stats.cell_per_spe[i] += p;
    }
    stats.ppe_cycles += sort_cycles;
    stats.modeled_pass_cycles +=
        cost_cycles + sort_cycles + claim_cycles + runtime_->last_run_cycles();
    // Host threads run the SPEs; their summed time is the measured parallel work.
    stats.busy_seconds += wall * std::min(n, static_cast<int>(std::thread::hardware_concurrency()));
    return absl::OkStatus();
  }

 private:
  Mesh& mesh_;
  const KernelConfig kernel_;
  CellOptions options_;
  std::unique_ptr<cellsim::Runtime> runtime_;
};

}  // namespace

absl::StatusOr<std::unique_ptr<RemovalBackend>> MakeCellBackend(Mesh& mesh,
                                                                const KernelConfig& kernel,
                                                                const CellOptions& options) {
  cellsim::RuntimeConfig config;
  config.num_spes = options.spes;
  config.spe.local_store_bytes = size_t(options.local_store_kib) * 1024;
  config.spe.cache.size_bytes = size_t(options.ls_cache_kib) * 1024;
  config.spe.thread_stack_bytes = kSoftwareThreadStack;
  absl::StatusOr<std::unique_ptr<cellsim::Runtime>> runtime = cellsim::Runtime::Create(config);
  if (!runtime.ok()) return runtime.status();
  for (absl::Status s : {
           (*runtime)->RegisterMainMemory(mesh.vertices(), mesh.vertex_capacity() * sizeof(VertexQ),
                                          "vertices"),
           (*runtime)->RegisterMainMemory(
               mesh.halfedges(), mesh.halfedge_capacity() * sizeof(HalfEdgeQ), "half-edges"),
           (*runtime)->RegisterMainMemory(mesh.status(), mesh.vertex_capacity() * sizeof(uint32_t),
                                          "status words"),
       })
    if (!s.ok()) return s;
  if (mesh.face_attrs() != nullptr)
    if (absl::Status s = (*runtime)->RegisterMainMemory(
            mesh.face_attrs(), mesh.face_capacity() * sizeof(FaceAttrQ), "face attributes");
        !s.ok())
      return s;
  if (mesh.quadrics() != nullptr)
    if (absl::Status s = (*runtime)->RegisterMainMemory(
            mesh.quadrics(), mesh.vertex_capacity() * sizeof(QuadricQ), "quadrics");
        !s.ok())
      return s;
  // The software threads' stacks must fit next to the cache: fail now with a clear message
  // rather than on the first pass.
  const size_t ls = config.spe.local_store_bytes, cache = config.spe.cache.size_bytes;
  const size_t stacks = size_t(options.spe_threads) * kSoftwareThreadStack;
  if (cache + stacks + cache / 4 > ls)
    return absl::ResourceExhaustedError(
        absl::StrCat("local store of ", ls / 1024, " KiB cannot hold a ", cache / 1024,
                     " KiB cache and ", options.spe_threads, " software thread stacks of ",
                     kSoftwareThreadStack / 1024, " KiB: lower --ls-cache-kib or --spe-threads"));
  return std::unique_ptr<RemovalBackend>(
      new CellBackend(mesh, kernel, options, *std::move(runtime)));
}

}  // namespace femsimp
