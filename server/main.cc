// femsimp-server: the gRPC simplification service.
#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <string>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "server/log.h"
#include "server/server.h"

ABSL_FLAG(std::string, listen, "127.0.0.1:50051", "gRPC address HOST:PORT");
ABSL_FLAG(std::string, metrics_listen, "127.0.0.1:9464",
          "Prometheus /metrics address HOST:PORT (empty: off)");
ABSL_FLAG(int, workers, 2, "jobs running at once");
ABSL_FLAG(int, queue_capacity, 16,
          "jobs waiting or uploading at most; more get RESOURCE_EXHAUSTED");
ABSL_FLAG(int, threads_per_job, 0,
          "engine threads per job, at most the host's cores (0: cores / workers)");
ABSL_FLAG(uint64_t, max_vertices, 20'000'000, "largest accepted mesh, in vertices");
ABSL_FLAG(uint64_t, max_faces, 40'000'000, "largest accepted mesh, in faces");
ABSL_FLAG(uint64_t, max_request_bytes, 8 << 20, "largest accepted request message, in bytes");
ABSL_FLAG(double, grace_period_seconds, 30.0,
          "on SIGTERM/SIGINT, time running jobs get to finish before they are cancelled");
ABSL_FLAG(double, max_connection_age_seconds, 0.0,
          "close client connections after this long (running calls finish first), so clients "
          "balancing over DNS re-resolve and find new replicas (0: never)");

int main(int argc, char** argv) {
  absl::SetProgramUsageMessage(
      "femsimp-server [flags]: serves femsimp.v1.Simplifier over gRPC, with health, "
      "reflection and Prometheus metrics. Exit codes: 0 stopped by a signal, 2 bad flags, "
      "3 cannot listen.");
  absl::ParseCommandLine(argc, argv);
  femsimp::server::ServerConfig config;
  config.listen = absl::GetFlag(FLAGS_listen);
  config.metrics_listen = absl::GetFlag(FLAGS_metrics_listen);
  config.workers = absl::GetFlag(FLAGS_workers);
  config.queue_capacity = absl::GetFlag(FLAGS_queue_capacity);
  config.threads_per_job = absl::GetFlag(FLAGS_threads_per_job);
  config.max_vertices = absl::GetFlag(FLAGS_max_vertices);
  config.max_faces = absl::GetFlag(FLAGS_max_faces);
  config.max_request_bytes = absl::GetFlag(FLAGS_max_request_bytes);
  config.grace_period_seconds = absl::GetFlag(FLAGS_grace_period_seconds);
  config.max_connection_age_seconds = absl::GetFlag(FLAGS_max_connection_age_seconds);
  if (std::string err = femsimp::server::NormalizeConfig(&config); !err.empty()) {
    std::fprintf(stderr, "femsimp-server: %s\n", err.c_str());
    return 2;
  }

  // Signals go to one waiting thread (this one), not to whichever thread gRPC happens to run.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  femsimp::server::FemsimpServer server(config);
  if (absl::Status s = server.Start(); !s.ok()) {
    std::fprintf(stderr, "femsimp-server: %s\n", std::string(s.message()).c_str());
    return 3;
  }
  int sig = 0;
  sigwait(&signals, &sig);
  femsimp::server::LogLine(sig == SIGTERM ? "SIGTERM received" : "SIGINT received");
  server.Shutdown();
  return 0;
}
