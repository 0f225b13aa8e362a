// The femsimp.v1.Simplifier gRPC service: admission, streaming of one job, job queries.
#pragma once

#include <atomic>

#include "femsimp/v1/femsimp.grpc.pb.h"
#include "server/auth.h"
#include "server/call_watchdog.h"
#include "server/config.h"
#include "server/job_queue.h"
#include "server/job_registry.h"
#include "server/job_runner.h"
#include "server/memory_budget.h"
#include "server/metrics.h"

namespace femsimp::server {

inline constexpr char kVersion[] = "0.1.0";

class SimplifierService final : public v1::Simplifier::Service {
 public:
  SimplifierService(const ServerConfig& config, JobQueue& queue, JobRegistry& registry,
                    JobRunner& runner, Metrics& metrics, TokenAuthenticator auth = {});
  size_t tenants() const { return auth_.tenants(); }
  const MemoryBudget& memory() const { return memory_; }

  grpc::Status Simplify(
      grpc::ServerContext* ctx,
      grpc::ServerReaderWriter<v1::SimplifyResponse, v1::SimplifyRequest>* stream) override;
  grpc::Status GetJob(grpc::ServerContext* ctx, const v1::GetJobRequest* req,
                      v1::JobInfo* resp) override;
  grpc::Status CancelJob(grpc::ServerContext* ctx, const v1::CancelJobRequest* req,
                         v1::CancelJobResponse* resp) override;
  grpc::Status ListJobs(grpc::ServerContext* ctx, const v1::ListJobsRequest* req,
                        v1::ListJobsResponse* resp) override;
  grpc::Status ServerInfo(grpc::ServerContext* ctx, const v1::ServerInfoRequest* req,
                          v1::ServerInfoResponse* resp) override;

  // New Simplify calls get UNAVAILABLE from now on.
  void BeginShutdown() { shutting_down_.store(true); }
  // Simplify handlers not yet returned (uploading, following a job, streaming its result).
  int active_simplify_calls() const { return active_simplify_calls_.load(); }

 private:
  // Everything after admission; the caller records the final status.
  grpc::Status RunJob(grpc::ServerContext* ctx,
                      grpc::ServerReaderWriter<v1::SimplifyResponse, v1::SimplifyRequest>* stream,
                      const std::shared_ptr<Job>& job, class RequestReader& reader,
                      const v1::JobSpec& spec, CallWatchdog::Watch& upload);
  // Streams progress until the job is done, then the Result (with the upload's repair report)
  // and the output; cancels the job when the client goes away.
  grpc::Status Follow(grpc::ServerContext* ctx,
                      grpc::ServerReaderWriter<v1::SimplifyResponse, v1::SimplifyRequest>* stream,
                      const std::shared_ptr<Job>& job, const RepairReport& repair);
  void UpdateQueueGauge();
  // RESOURCE_EXHAUSTED with the server's retry pushback: capacity that frees up (queue slots,
  // a tenant's jobs, memory).
  grpc::Status Pushback(grpc::ServerContext* ctx, const std::string& why) const;
  // The caller's job `id`, when it exists and is the caller's tenant's (another tenant's job is
  // NOT_FOUND, as if it did not exist).
  grpc::Status FindOwnJob(const grpc::ServerContext* ctx, const std::string& id,
                          std::shared_ptr<Job>* job) const;

  const ServerConfig& config_;
  JobQueue& queue_;
  JobRegistry& registry_;
  JobRunner& runner_;
  Metrics& metrics_;
  MemoryBudget memory_;
  CallWatchdog watchdog_;
  std::atomic<bool> shutting_down_{false};
  std::atomic<int> active_simplify_calls_{0};
  const TokenAuthenticator auth_;
};

}  // namespace femsimp::server
