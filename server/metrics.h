// Prometheus metrics of the service (femsimp_ prefix), pulled from their own HTTP port.
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "engine/repair.h"
#include "engine/simplify.h"
#include "grpcpp/support/status.h"
#include "prometheus/counter.h"
#include "prometheus/family.h"
#include "prometheus/gauge.h"
#include "prometheus/histogram.h"
#include "prometheus/registry.h"
#include "server/metrics_http.h"

namespace femsimp::server {

// Modeled Cell speedup of a finished job: the SPEs' modeled cycles run one after the other
// (plus the PPE share) over the modeled parallel cycles. An estimate: it ignores that one SPE
// alone would see other cache behaviour. HOOK: replace with the engine's own one-SPE model
// once SimplifyResult carries one. nullopt on native or without cell counters.
std::optional<double> ModeledSpeedup(const SimplifyResult& r);

// The stages of a job on the server, each observed once per job that gets through it
// (femsimp_stage_duration_seconds{stage, backend}): upload (the spec's Accepted to the last
// chunk, decoded into the soup), repair and build (PrepareMesh's two steps), engine (Simplify),
// encode (the output compacted and cut into chunks), download (the result stream's writes).
enum class Stage { kUpload, kRepair, kBuild, kEngine, kEncode, kDownload };
const char* StageName(Stage stage);

class Metrics {
 public:
  Metrics();
  // Serves /metrics on HOST:PORT (port 0 picks a free one; server/metrics_http.h).
  absl::Status StartExposer(const std::string& address);
  int port() const;  // the /metrics port, 0 when not started

  // femsimp_jobs_total{status[, tenant]}: the tenant label only on a server with tenants.
  void JobFinished(grpc::StatusCode code, const std::string& tenant = "");
  void SetQueueDepth(size_t waiting);
  void SetRunning(int running);
  // femsimp_memory_admitted_bytes (the estimates of the admitted jobs) and
  // femsimp_memory_budget_bytes (--memory_budget_mib).
  void SetMemoryAdmitted(uint64_t bytes);
  void SetMemoryBudget(uint64_t bytes);
  void PassFinished(Backend backend, const PassStats& p);
  // The repair stage's changes to an uploaded mesh, per kind (femsimp_repairs_total{kind}).
  void Repaired(const RepairReport& report);
  void JobCompleted(Backend backend, int contexts, double job_seconds, double queue_seconds,
                    const SimplifyResult& r);
  void StageFinished(Stage stage, Backend backend, double seconds);

 private:
  std::shared_ptr<prometheus::Registry> registry_;
  std::unique_ptr<MetricsHttpServer> http_;
  std::mutex mu_;  // Family::Add is thread-safe; mu_ only guards http_
  prometheus::Family<prometheus::Counter>& jobs_;
  prometheus::Gauge& queue_depth_;
  prometheus::Gauge& running_;
  prometheus::Gauge& memory_admitted_;
  prometheus::Gauge& memory_budget_;
  prometheus::Family<prometheus::Histogram>& job_seconds_;
  prometheus::Family<prometheus::Histogram>& queue_seconds_;
  prometheus::Family<prometheus::Histogram>& pass_seconds_;
  prometheus::Family<prometheus::Histogram>& stage_seconds_;
  prometheus::Family<prometheus::Counter>& passes_;
  prometheus::Counter& vertices_in_;
  prometheus::Counter& vertices_out_;
  prometheus::Counter& vertices_removed_;
  prometheus::Counter& faces_in_;
  prometheus::Counter& faces_out_;
  prometheus::Family<prometheus::Counter>& lock_conflicts_;
  prometheus::Counter& seam_points_removed_;
  prometheus::Family<prometheus::Counter>& rejections_;
  prometheus::Family<prometheus::Counter>& repairs_;
  prometheus::Counter& cache_hits_;
  prometheus::Counter& cache_misses_;
  prometheus::Family<prometheus::Histogram>& speedup_;
  prometheus::Family<prometheus::Gauge>& last_speedup_;
  prometheus::Family<prometheus::Histogram>& modeled_speedup_;
  prometheus::Family<prometheus::Gauge>& last_modeled_speedup_;
};

}  // namespace femsimp::server
