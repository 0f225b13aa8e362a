#include "server/metrics.h"

#include <exception>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "server/job.h"

namespace femsimp::server {
namespace {

using prometheus::Histogram;

const Histogram::BucketBoundaries kJobBuckets = {0.01, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 300};
const Histogram::BucketBoundaries kPassBuckets = {0.0003, 0.001, 0.003, 0.01, 0.03,
                                                  0.1,    0.3,   1,     3,    10};
const Histogram::BucketBoundaries kStageBuckets = {0.001, 0.003, 0.01, 0.03, 0.1, 0.3,
                                                   1,     3,     10,   30,   100, 300};
const Histogram::BucketBoundaries kSpeedupBuckets = {0.5, 1, 1.5, 2, 3, 4, 6, 8, 12, 16, 32, 64};

const char* BackendLabel(Backend backend) { return backend == Backend::kCell ? "cell" : "native"; }

}  // namespace

const char* StageName(Stage stage) {
  switch (stage) {
    case Stage::kUpload:
      return "upload";
    case Stage::kRepair:
      return "repair";
    case Stage::kBuild:
      return "build";
    case Stage::kEngine:
      return "engine";
    case Stage::kEncode:
      return "encode";
    case Stage::kDownload:
      return "download";
  }
  return "unknown";
}

std::optional<double> ModeledSpeedup(const SimplifyResult& r) {
  double sequential = 0, parallel = 0;
  for (const PassStats& p : r.passes) {
    if (!p.cell) continue;
    double spe_sum = 0;
    for (const CellPassCounters& c : p.cell_per_spe)
      spe_sum += static_cast<double>(c.modeled_cycles);
    if (p.cell_per_spe.empty()) spe_sum = static_cast<double>(p.cell->modeled_cycles);
    sequential += spe_sum + static_cast<double>(p.ppe_cycles);
    parallel += static_cast<double>(p.modeled_pass_cycles);
  }
  if (parallel <= 0 || sequential <= 0) return std::nullopt;
  return sequential / parallel;
}

Metrics::Metrics()
    : registry_(std::make_shared<prometheus::Registry>()),
      jobs_(prometheus::BuildCounter()
                .Name("femsimp_jobs_total")
                .Help("Simplify calls by final gRPC status (rejected ones included)")
                .Register(*registry_)),
      queue_depth_(prometheus::BuildGauge()
                       .Name("femsimp_queue_depth")
                       .Help("Jobs waiting for a worker")
                       .Register(*registry_)
                       .Add({})),
      running_(prometheus::BuildGauge()
                   .Name("femsimp_running_jobs")
                   .Help("Jobs running on a worker")
                   .Register(*registry_)
                   .Add({})),
      memory_admitted_(prometheus::BuildGauge()
                           .Name("femsimp_memory_admitted_bytes")
                           .Help("Estimated peak memory of the admitted jobs (uploading, "
                                 "queued, running or streaming their result)")
                           .Register(*registry_)
                           .Add({})),
      memory_budget_(prometheus::BuildGauge()
                         .Name("femsimp_memory_budget_bytes")
                         .Help("Memory the admitted jobs' estimates may add up to "
                               "(--memory_budget_mib)")
                         .Register(*registry_)
                         .Add({})),
      job_seconds_(prometheus::BuildHistogram()
                       .Name("femsimp_job_duration_seconds")
                       .Help("Engine wall time of finished jobs")
                       .Register(*registry_)),
      queue_seconds_(prometheus::BuildHistogram()
                         .Name("femsimp_queue_wait_seconds")
                         .Help("Time finished jobs waited for a worker")
                         .Register(*registry_)),
      pass_seconds_(prometheus::BuildHistogram()
                        .Name("femsimp_pass_duration_seconds")
                        .Help("Wall time of one simplification pass")
                        .Register(*registry_)),
      stage_seconds_(prometheus::BuildHistogram()
                         .Name("femsimp_stage_duration_seconds")
                         .Help("Wall time of each stage of a job on the server (upload, repair, "
                               "build, engine, encode, download)")
                         .Register(*registry_)),
      passes_(prometheus::BuildCounter()
                  .Name("femsimp_passes_total")
                  .Help("Simplification passes run")
                  .Register(*registry_)),
      vertices_in_(prometheus::BuildCounter()
                       .Name("femsimp_vertices_in_total")
                       .Help("Input vertices of finished jobs")
                       .Register(*registry_)
                       .Add({})),
      vertices_out_(prometheus::BuildCounter()
                        .Name("femsimp_vertices_out_total")
                        .Help("Output vertices of finished jobs")
                        .Register(*registry_)
                        .Add({})),
      vertices_removed_(prometheus::BuildCounter()
                            .Name("femsimp_vertices_removed_total")
                            .Help("Vertices removed, counted per pass")
                            .Register(*registry_)
                            .Add({})),
      faces_in_(prometheus::BuildCounter()
                    .Name("femsimp_faces_in_total")
                    .Help("Input faces of finished jobs")
                    .Register(*registry_)
                    .Add({})),
      faces_out_(prometheus::BuildCounter()
                     .Name("femsimp_faces_out_total")
                     .Help("Output faces of finished jobs")
                     .Register(*registry_)
                     .Add({})),
      lock_conflicts_(prometheus::BuildCounter()
                          .Name("femsimp_lock_conflicts_total")
                          .Help("Candidates given up because a one-ring vertex was locked")
                          .Register(*registry_)),
      seam_points_removed_(prometheus::BuildCounter()
                               .Name("femsimp_seam_points_removed_total")
                               .Help("Assembly seam points slid along their seams (all copies)")
                               .Register(*registry_)
                               .Add({})),
      rejections_(prometheus::BuildCounter()
                      .Name("femsimp_rejections_total")
                      .Help("Candidates given up, by criterion")
                      .Register(*registry_)),
      repairs_(prometheus::BuildCounter()
                   .Name("femsimp_repairs_total")
                   .Help("Changes the repair stage made to uploaded meshes, by kind")
                   .Register(*registry_)),
      cache_hits_(prometheus::BuildCounter()
                      .Name("femsimp_cell_cache_hits_total")
                      .Help("Cell back end: software cache hits")
                      .Register(*registry_)
                      .Add({})),
      cache_misses_(prometheus::BuildCounter()
                        .Name("femsimp_cell_cache_misses_total")
                        .Help("Cell back end: software cache misses")
                        .Register(*registry_)
                        .Add({})),
      speedup_(prometheus::BuildHistogram()
                   .Name("femsimp_parallel_speedup")
                   .Help("Measured parallel speedup of finished jobs (busy / engine seconds)")
                   .Register(*registry_)),
      last_speedup_(prometheus::BuildGauge()
                        .Name("femsimp_parallel_speedup_last")
                        .Help("Measured parallel speedup of the last finished job")
                        .Register(*registry_)),
      modeled_speedup_(prometheus::BuildHistogram()
                           .Name("femsimp_cell_modeled_speedup")
                           .Help("Cell back end: modeled speedup over one SPE (estimate)")
                           .Register(*registry_)),
      last_modeled_speedup_(prometheus::BuildGauge()
                                .Name("femsimp_cell_modeled_speedup_last")
                                .Help("Cell back end: modeled speedup of the last finished job")
                                .Register(*registry_)) {}

absl::Status Metrics::StartExposer(const std::string& address) {
  std::lock_guard<std::mutex> lock(mu_);
  absl::StatusOr<std::unique_ptr<MetricsHttpServer>> http =
      MetricsHttpServer::Start(address, registry_);
  if (!http.ok()) return http.status();
  http_ = std::move(*http);
  return absl::OkStatus();
}

int Metrics::port() const {
  auto* self = const_cast<Metrics*>(this);
  std::lock_guard<std::mutex> lock(self->mu_);
  return http_ ? http_->port() : 0;
}

void Metrics::JobFinished(grpc::StatusCode code, const std::string& tenant) {
  if (tenant.empty())
    jobs_.Add({{"status", StatusCodeName(code)}}).Increment();
  else
    jobs_.Add({{"status", StatusCodeName(code)}, {"tenant", tenant}}).Increment();
}

void Metrics::SetQueueDepth(size_t waiting) { queue_depth_.Set(static_cast<double>(waiting)); }
void Metrics::SetRunning(int running) { running_.Set(running); }
void Metrics::SetMemoryAdmitted(uint64_t bytes) {
  memory_admitted_.Set(static_cast<double>(bytes));
}
void Metrics::SetMemoryBudget(uint64_t bytes) { memory_budget_.Set(static_cast<double>(bytes)); }

void Metrics::PassFinished(Backend backend, const PassStats& p) {
  const std::string b = BackendLabel(backend);
  pass_seconds_.Add({{"backend", b}}, kPassBuckets).Observe(p.seconds);
  passes_.Add({{"backend", b}}).Increment();
  vertices_removed_.Increment(static_cast<double>(p.removed));
  lock_conflicts_.Add({{"backend", b}}).Increment(static_cast<double>(p.lock_conflicts));
  seam_points_removed_.Increment(static_cast<double>(p.seam_points_removed));
  for (int i = 0; i < static_cast<int>(Reject::kCount); ++i)
    if (p.rejections[i])
      rejections_.Add({{"criterion", RejectName(static_cast<Reject>(i))}})
          .Increment(static_cast<double>(p.rejections[i]));
  if (p.cell) {
    cache_hits_.Increment(static_cast<double>(p.cell->cache_hits));
    cache_misses_.Increment(static_cast<double>(p.cell->cache_misses));
  }
}

void Metrics::Repaired(const RepairReport& report) {
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (report.counts[k] > 0)
      repairs_.Add({{"kind", RepairKindName(static_cast<RepairKind>(k))}})
          .Increment(static_cast<double>(report.counts[k]));
}

void Metrics::JobCompleted(Backend backend, int contexts, double job_seconds, double queue_seconds,
                           const SimplifyResult& r) {
  const std::string b = BackendLabel(backend);
  const prometheus::Labels labels = {{"backend", b}, {"contexts", std::to_string(contexts)}};
  job_seconds_.Add({{"backend", b}}, kJobBuckets).Observe(job_seconds);
  queue_seconds_.Add({}, kJobBuckets).Observe(queue_seconds);
  vertices_in_.Increment(static_cast<double>(r.input_vertices));
  vertices_out_.Increment(static_cast<double>(r.output_vertices));
  faces_in_.Increment(static_cast<double>(r.input_faces));
  faces_out_.Increment(static_cast<double>(r.output_faces));
  if (r.engine_seconds > 0) {
    double s = r.busy_seconds / r.engine_seconds;
    speedup_.Add(labels, kSpeedupBuckets).Observe(s);
    last_speedup_.Add(labels).Set(s);
  }
  if (backend == Backend::kCell) {
    if (std::optional<double> m = ModeledSpeedup(r)) {
      modeled_speedup_.Add(labels, kSpeedupBuckets).Observe(*m);
      last_modeled_speedup_.Add(labels).Set(*m);
    }
  }
}

void Metrics::StageFinished(Stage stage, Backend backend, double seconds) {
  stage_seconds_
      .Add({{"stage", StageName(stage)}, {"backend", BackendLabel(backend)}}, kStageBuckets)
      .Observe(seconds);
}

}  // namespace femsimp::server
