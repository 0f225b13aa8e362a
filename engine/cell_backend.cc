// The cell back end: the removal kernel on N emulated SPEs (cellsim), one kernel per software
// thread, each SPE visiting its share of the candidates in cost order.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "absl/strings/str_cat.h"
#include "engine/cell_port.h"
#include "engine/removal_backend.h"
#include "engine/spatial_key.h"

namespace femsimp {
namespace {

// Modeled cycles of the work done outside the SPE kernel (documented in docs/CELLSIM.md):
// the cost of one vertex (one-ring walk and angle sum, parallel over the SPEs as in the paper)
// and one comparison-and-move of a sort on the PPE. The pass's sort runs on the SPEs
// (SortPass); the PPE sorts only in the rounds' choice of winners.
constexpr uint64_t kCostCyclesPerVertex = 400;
constexpr uint64_t kSortCyclesPerElementLevel = 8;
// From the second pass on, the vertices to cost come from lists (the last selection, the
// requeued vertices): the SPEs drop the duplicates with a mark per vertex, set and cleared
// (ListMergeCycles).
constexpr uint64_t kListMergeCyclesPerVertex = 24;
// Deterministic rounds (engine/rounds.h): each candidate's fan box (its one-ring walk, as for
// the cost) is one more SPE run, parallel over the SPEs; choosing the winners (a sort of the
// boxes and a sweep, greedy in cost order) is PPE work.
constexpr uint64_t kFanBoxCyclesPerCandidate = 400;
// The free schedule's order (OrderBySpace): a candidate's spatial key, from the vertex the
// cost phase has just read (three scalings and a bit interleave).
constexpr uint64_t kSpatialKeyCyclesPerCandidate = 40;
// The free schedule's chunks hold at most this many candidates: a compact patch whose rings an
// SPE's 64 KiB cache keeps (blade3, pass 1 at 8 SPEs: hit ratio 76.5 % with chunks of up to
// 1/2N of the candidates, 82.2 % with 1,024, 87.4 % with 256, 88.0 % with 128), each chunk
// still in cost order. Every chunk costs one visit to the shared index.
constexpr uint64_t kFreeChunkCandidates = 256;
// A software thread's stack, from its SPE's local store: the kernel's state (two copies of its
// fan's side data, 2 KiB each) and the rules' frames. The deepest candidate, a full-edge
// collapse, took 35 KiB (Release) and 49 KiB (AddressSanitizer's frames) when it was raised
// from 48 KiB; the default local store still holds the 64 KiB cache and three of them.
constexpr size_t kSoftwareThreadStack = 56 * 1024;

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
      : mesh_(mesh),
        kernel_(kernel),
        options_(options),
        runtime_(std::move(runtime)),
        spatial_(mesh.vertices(), mesh.vertex_capacity()) {}

  int contexts() const override { return runtime_->num_spes(); }

  // Allocates the sort's keys and scratch (one per vertex, whole quadwords) and lets the SPEs
  // reach them.
  absl::Status AllocateSortKeys() {
    const size_t n = std::max<size_t>(2, (size_t(mesh_.vertex_capacity()) + 1) & ~size_t{1});
    for (int i = 0; i < 2; ++i) {
      keys_[i].assign(n, 0);
      if (absl::Status s = runtime_->RegisterMainMemory(keys_[i].data(), n * sizeof(uint64_t),
                                                        i == 0 ? "sort keys" : "sort scratch");
          !s.ok())
        return s;
    }
    return absl::OkStatus();
  }

  absl::Status RunRemoval(const RemovalPhase& phase, PassStats& stats) override {
    const int n = runtime_->num_spes();
    runtime_->ResetCounters();
    uint64_t pick_cycles = 0, cost_cycles = 0, claim_cycles = 0, spe_sort_cycles = 0;
    if (phase.pass_start) {
      // SPEs: the cost of every vertex the selection looked at, split evenly, after merging
      // the lists of those to look at; then they sort the removable vertices.
      cost_cycles = kCostCyclesPerVertex * phase.looked / n + ListMergeCycles(phase.merged);
      absl::StatusOr<uint64_t> sorted = SortPass(phase);
      if (!sorted.ok()) return sorted.status();
      spe_sort_cycles = *sorted;
    }
    // Deterministic rounds (phase.claimed > 0): their SPE program is launched for the fan boxes
    // of the pass's first round and stays resident until the pass ends; every later round's
    // fan boxes start with a wake-up and end with a report (CostModel::ResidentSyncCycles), not
    // a launch and a join. The SPEs go on from their fan boxes to the round's winners as the PPE
    // publishes them (RunStart::kHandOff): no wake-up between the two.
    const bool rounds = phase.claimed > 0;
    uint64_t start_cycles = 0;
    if (rounds) {
      const double claimed = static_cast<double>(phase.claimed);
      const uint64_t boxes_start = runtime_->StartCycles(
          phase.pass_start ? cellsim::RunStart::kLaunch : cellsim::RunStart::kResident);
      claim_cycles = kFanBoxCyclesPerCandidate * phase.claimed / n + boxes_start;
      start_cycles += boxes_start;
      pick_cycles = static_cast<uint64_t>(
          claimed * std::max(1.0, std::log2(std::max(2.0, claimed))) * kSortCyclesPerElementLevel);
    }

    // The SPEs share the work out as they go (WorkPlan::Guided: shrinking chunks from one
    // shared index, taken in modeled time), so that an SPE that drew cheap candidates takes
    // more and none waits long for the slowest. A round's winners go in the order the PPE
    // picks them, each as soon as it is picked (PublishPicks), so that the SPEs work while the
    // PPE picks; the free schedule's candidates in small chunks of a spatial order, each chunk
    // in cost order (OrderBySpace). One SPE of the free schedule keeps its single list (the
    // paper's program, and the native back end's order at one thread).
    const bool guided = n > 1 || rounds;
    const uint32_t* items = phase.candidates;
    const uint64_t* published = nullptr;
    std::vector<std::span<const uint32_t>> spans;
    uint64_t split_cycles = 0;
    if (!guided) {
      spans.emplace_back(phase.candidates, phase.count);
    } else if (rounds) {
      if (absl::Status s = PublishPicks(phase, pick_cycles); !s.ok()) return s;
      items = picked_.data();
      published = published_.data();
    } else if (!phase.blocks) {
      absl::StatusOr<uint64_t> split = OrderBySpace(phase, n);
      if (!split.ok()) return split.status();
      split_cycles = *split;
      items = order_.data();
    }
    const cellsim::RunStart removal_start =
        rounds ? cellsim::RunStart::kHandOff : cellsim::RunStart::kLaunch;
    std::vector<KernelStats> per_spe = ContextStats(phase, n);
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
                                           kstats, kernel_.placement, kernel_.requeue_changed);
            RunCandidates(kernel, phase, [&ctx, items, guided]() -> std::optional<uint32_t> {
              const std::optional<uint64_t> v = ctx.NextWorkItem();
              if (!v) return std::nullopt;
              return guided ? items[*v] : static_cast<uint32_t>(*v);
            });
          });
          if (!s.ok()) spe.ReportError(s);
        },
        guided ? cellsim::WorkPlan::Guided(phase.count, FreeChunkLimit(phase), published)
               : cellsim::WorkPlan::PerSpe(std::move(spans)),
        removal_start);
    start_cycles += runtime_->StartCycles(removal_start);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!status.ok()) return status;

    // A pass may run as several phases (deterministic rounds): the counters add up.
    if (!stats.cell) stats.cell.emplace();
    stats.cell_per_spe.resize(n);
    for (int i = 0; i < n; ++i) {
      AddKernelStats(per_spe[i], phase, stats);
      CellPassCounters p = ToPassCounters(runtime_->spe(i).counters());
      p.stale_reread = per_spe[i].stale_reread;
      p.stale_skipped = per_spe[i].inconsistent;
      *stats.cell += p;
      stats.cell_per_spe[i] += p;
    }
    // The PPE's pick runs beside the removal run: the round lasts until both are done.
    stats.ppe_cycles += pick_cycles;
    stats.spe_start_cycles += start_cycles;
    const uint64_t removal_cycles =
        std::max(runtime_->last_run_cycles(), runtime_->StartCycles(removal_start) + pick_cycles);
    stats.modeled_pass_cycles +=
        cost_cycles + spe_sort_cycles + split_cycles + claim_cycles + removal_cycles;
    // Host threads run the SPEs; their summed time is the measured parallel work.
    stats.busy_seconds += wall * std::min(n, static_cast<int>(std::thread::hardware_concurrency()));
    return absl::OkStatus();
  }

 private:
  // Merging the lists of vertices to cost, `merged` vertices once duplicates are dropped, on
  // the SPEs. Each SPE owns an equal range of vertex ids and keeps a mark per vertex of its
  // range in its local store (a bit each: 64 KiB for 520 k vertices on one SPE). The SPEs
  // that made the lists (the last selection, the kernels' requeued vertices) put each id in
  // its owner's bucket as they made it; an owner fetches its buckets, one DMA get from every
  // SPE, sets a mark per id and reads the marks off in vertex order, clearing them
  // (kListMergeCyclesPerVertex a vertex, as the PPE's mark did); one barrier between the
  // buckets and the marks. Every id crosses main memory twice (put, then get).
  uint64_t ListMergeCycles(size_t merged) const {
    if (merged == 0) return 0;
    const int n = runtime_->num_spes();
    const cellsim::CostModel& cost = runtime_->spe(0).config().cost;
    const uint64_t gets = uint64_t(n) * cost.dma_issue_cycles + cost.dma_latency_cycles;
    const uint64_t moved = cost.MemoryCycles(2 * sizeof(uint32_t) * merged, n);
    return kListMergeCyclesPerVertex * merged / n + gets + moved + cost.ResidentSyncCycles(n);
  }

  // The pass's sort on the SPEs (cellsim/spe_sort.h); returns its modeled cycles. The SPEs
  // sort what the cost phase leaves in main memory, one key per removable vertex in vertex
  // order. The key used here is the vertex's rank in the order the engine made (its host
  // sort) above its id: it orders as the cost keys do, so every comparison and move is the one
  // the cost keys would take, and the SPEs' result can be checked against that order.
  absl::StatusOr<uint64_t> SortPass(const RemovalPhase& phase) {
    if (phase.sorted == 0) return 0;  // (an empty order may have no array at all)
    if (phase.order == nullptr)
      return absl::InternalError("cell back end: a pass started without its order of vertices");
    const uint32_t nv = mesh_.vertex_capacity();
    rank_.assign(nv, kNone);
    for (size_t i = 0; i < phase.sorted; ++i) rank_[phase.order[i]] = static_cast<uint32_t>(i);
    uint64_t* keys = keys_[0].data();
    size_t m = 0;
    for (uint32_t v = 0; v < nv; ++v)
      if (rank_[v] != kNone) keys[m++] = (uint64_t{rank_[v]} << 32) | v;
    if (m % 2 != 0) keys[m++] = ~uint64_t{0};  // the sort takes whole quadwords
    absl::StatusOr<cellsim::SpeSortStats> sorted =
        cellsim::SortOnSpes(*runtime_, keys, keys_[1].data(), m);
    if (!sorted.ok()) return sorted.status();
    for (size_t i = 0; i < phase.sorted; ++i)
      if (keys[i] != ((uint64_t{i} << 32) | phase.order[i]))
        return absl::InternalError(absl::StrCat(
            "cell back end: the SPEs' sort put vertex ", uint32_t(keys[i]), " at position ", i,
            " of the pass's order, which has vertex ", phase.order[i], " there"));
    return sorted->elapsed_cycles;
  }

  // A round's winners in the order the PPE picks them (their places in the window), each
  // published when the pick, going through the window at an even pace (`pick_cycles` in all),
  // reaches it, so that the SPEs start on the first while the PPE picks the rest. (Handing
  // over only the first few as picked and the rest in vertex order when the pick is done, for
  // the cache, was tried: blade3 at 8 SPEs took 0.8 % longer, as the SPEs waited for the big
  // rounds' picks.) Without the places, every winner is published when the pick ends.
  absl::Status PublishPicks(const RemovalPhase& phase, uint64_t pick_cycles) {
    const size_t count = phase.count, claimed = phase.claimed;
    picked_.resize(count);
    published_.resize(count);
    if (phase.window_rank == nullptr) {
      std::copy(phase.candidates, phase.candidates + count, picked_.begin());
      std::fill(published_.begin(), published_.end(), pick_cycles);
      return absl::OkStatus();
    }
    by_rank_.assign(claimed, kNone);
    for (size_t i = 0; i < count; ++i) {
      const uint32_t rank = phase.window_rank[i];
      if (rank >= claimed || by_rank_[rank] != kNone)
        return absl::InternalError(absl::StrCat("cell back end: winner ", phase.candidates[i],
                                                " has place ", rank, " in a window of ", claimed,
                                                ", not a place of its own"));
      by_rank_[rank] = static_cast<uint32_t>(i);
    }
    size_t j = 0;
    for (size_t k = 0; k < claimed; ++k) {
      if (by_rank_[k] == kNone) continue;
      picked_[j] = phase.candidates[by_rank_[k]];
      published_[j++] = (k + 1) * pick_cycles / claimed;
    }
    return absl::OkStatus();
  }

  static uint64_t FreeChunkLimit(const RemovalPhase& phase) {
    return phase.blocks ? cellsim::WorkPlan::kAnyChunk : kFreeChunkCandidates;
  }

  // The free schedule's order for a guided run: the candidates cut into the run's chunks
  // (GuidedDispenser::ChunkSize, the same sequence whoever asks) along a spatial order, each
  // chunk in cost order (as the paper's split keeps an SPE's candidates), so that an SPE's
  // neighbourhoods lie together (more cache hits). The spatial order is split into n lanes,
  // and chunk j comes from lane j mod n, where the lane's last chunk ended: the chunks served
  // one after the other, which SPEs work on at once, lie apart, so their neighbourhoods rarely
  // meet (fewer lock conflicts; an SPE ends up sweeping a lane as the paper's split had it
  // sweep a region). The SPEs compute the candidates' spatial keys and sort them (with the
  // index in cost order below the key); returns the modeled cycles. Fills order_.
  absl::StatusOr<uint64_t> OrderBySpace(const RemovalPhase& phase, int n) {
    const size_t count = phase.count;
    uint64_t* keys = keys_[0].data();
    for (size_t i = 0; i < count; ++i)
      keys[i] = (uint64_t{spatial_(mesh_.vertices()[phase.candidates[i]])} << 32) | i;
    size_t m = count;
    if (m % 2 != 0) keys[m++] = ~uint64_t{0};
    absl::StatusOr<cellsim::SpeSortStats> sorted =
        cellsim::SortOnSpes(*runtime_, keys, keys_[1].data(), m);
    if (!sorted.ok()) return sorted.status();
    // The chunks' sizes, and each lane's share of the spatial order (its chunks' total).
    chunk_sizes_.clear();
    for (size_t first = 0; first < count; first += chunk_sizes_.back())
      chunk_sizes_.push_back(
          cellsim::GuidedDispenser::ChunkSize(count - first, n, FreeChunkLimit(phase)));
    lane_next_.assign(size_t(n) + 1, 0);
    for (size_t j = 0; j < chunk_sizes_.size(); ++j) lane_next_[j % n + 1] += chunk_sizes_[j];
    for (int lane = 1; lane <= n; ++lane) lane_next_[lane] += lane_next_[lane - 1];
    // Each candidate's chunk (by the chunk's first slot), then the candidates placed chunk by
    // chunk in cost order: fill_[first] is that chunk's next free slot.
    chunk_of_.resize(count);
    fill_.resize(count);
    for (size_t j = 0, first = 0; j < chunk_sizes_.size(); first += chunk_sizes_[j++]) {
      size_t& from = lane_next_[j % n];  // the lane's next rank in the spatial order
      for (size_t r = from; r < from + chunk_sizes_[j]; ++r)
        chunk_of_[uint32_t(keys[r])] = uint32_t(first);
      from += chunk_sizes_[j];
      fill_[first] = uint32_t(first);
    }
    order_.resize(count);
    for (size_t i = 0; i < count; ++i) order_[fill_[chunk_of_[i]]++] = phase.candidates[i];
    return kSpatialKeyCyclesPerCandidate * count / n + sorted->elapsed_cycles;
  }

  Mesh& mesh_;
  const KernelConfig kernel_;
  CellOptions options_;
  std::unique_ptr<cellsim::Runtime> runtime_;
  // The sort's keys and its scratch in main memory (registered), and the ranks it starts from.
  // (operator new aligns them to 16 bytes, as DMA needs)
  std::array<std::vector<uint64_t>, 2> keys_;
  std::vector<uint32_t> rank_;
  const SpatialKey spatial_;
  // OrderBySpace: the chunks' sizes, each lane's next rank, each candidate's chunk, each
  // chunk's next free slot, and the candidates chunk by chunk.
  std::vector<size_t> chunk_sizes_, lane_next_;
  std::vector<uint32_t> chunk_of_, fill_, order_;
  // PublishPicks: the winners by place in the window, in pick order, and when each is out.
  std::vector<uint32_t> by_rank_, picked_;
  std::vector<uint64_t> published_;
};

}  // namespace

absl::StatusOr<std::unique_ptr<RemovalBackend>> MakeCellBackend(Mesh& mesh,
                                                                const KernelConfig& kernel,
                                                                const CellOptions& options) {
  cellsim::RuntimeConfig config;
  config.num_spes = options.spes;
  config.spe.local_store_bytes = size_t(options.local_store_kib) * 1024;
  config.spe.cache.size_bytes = size_t(options.ls_cache_kib) * 1024;
  config.spe.cache.line_bytes = size_t(options.ls_cache_line_bytes);
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
  // The software threads' stacks, and between runs the sort's buffers, must fit next to the
  // cache: fail now with a clear message rather than on the first pass.
  const size_t ls = config.spe.local_store_bytes, cache = config.spe.cache.size_bytes;
  const size_t stacks = size_t(options.spe_threads) * kSoftwareThreadStack;
  if (cache + stacks + cache / 4 > ls)
    return absl::ResourceExhaustedError(
        absl::StrCat("local store of ", ls / 1024, " KiB cannot hold a ", cache / 1024,
                     " KiB cache and ", options.spe_threads, " software thread stacks of ",
                     kSoftwareThreadStack / 1024, " KiB: lower --ls-cache-kib or --spe-threads"));
  if (cache + cellsim::kSortLsBytes + cache / 4 > ls)
    return absl::ResourceExhaustedError(absl::StrCat(
        "local store of ", ls / 1024, " KiB cannot hold a ", cache / 1024, " KiB cache and the ",
        cellsim::kSortLsBytes / 1024, " KiB the SPEs sort in: lower --ls-cache-kib"));
  auto backend = std::make_unique<CellBackend>(mesh, kernel, options, *std::move(runtime));
  if (absl::Status s = backend->AllocateSortKeys(); !s.ok()) return s;
  return std::unique_ptr<RemovalBackend>(std::move(backend));
}

}  // namespace femsimp
