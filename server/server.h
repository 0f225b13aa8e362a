// A femsimp server with everything it runs: gRPC service, health, reflection, queue, workers,
// metrics. Used by main.cc and, in process, by the tests.
#pragma once

#include <memory>

#include "absl/status/status.h"
#include "grpcpp/server.h"
#include "server/config.h"
#include "server/job_queue.h"
#include "server/job_registry.h"
#include "server/job_runner.h"
#include "server/metrics.h"
#include "server/service.h"

namespace femsimp::server {

class FemsimpServer {
 public:
  explicit FemsimpServer(ServerConfig config);
  ~FemsimpServer();

  // Binds the gRPC and metrics ports (port 0 picks free ones) and starts the workers.
  absl::Status Start();
  int port() const { return port_; }
  int metrics_port() const { return metrics_.port(); }
  const ServerConfig& config() const { return config_; }

  // Graceful stop: health NOT_SERVING, no new jobs, queued jobs end UNAVAILABLE, running jobs
  // get grace_period_seconds to finish and are cancelled after that. Idempotent.
  void Shutdown();

 private:
  ServerConfig config_;
  Metrics metrics_;
  JobQueue queue_;
  JobRegistry registry_;
  std::unique_ptr<JobRunner> runner_;
  std::unique_ptr<SimplifierService> service_;
  std::unique_ptr<grpc::Server> server_;
  int port_ = 0;
  bool stopped_ = false;
};

}  // namespace femsimp::server
