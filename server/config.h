// Server settings (filled from flags in main.cc, directly by the tests).
#pragma once

#include <cstdint>
#include <string>

#include "common/flags.h"

namespace femsimp::server {

struct ServerConfig {
  std::string listen = "127.0.0.1:50051";
  std::string metrics_listen = "127.0.0.1:9464";  // empty: no metrics exposer
  int workers = 2;                                // jobs running at once
  int queue_capacity = 16;                        // jobs waiting (or uploading) at most
  int threads_per_job = 0;                        // 0: host cores / workers (at least 1)
  uint64_t max_vertices = 20'000'000;
  uint64_t max_faces = 40'000'000;
  uint64_t max_request_bytes = 8 << 20;  // per received message
  // What the admitted jobs' estimated peaks (server/memory_budget.h) may add up to; 0 until
  // NormalizeConfig sets 3/4 of the memory this process may use (physical or cgroup limit).
  uint64_t memory_budget_mib = 0;
  // The cell back end per job: each SPE is a host thread with its own emulated local store.
  int max_spes = 32;
  int max_cell_local_store_mib = 256;  // SPEs x local store size
  double grace_period_seconds = 30.0;
  // Uploads (the spec and the mesh chunks): a call sending nothing for this long, or not done
  // after the deadline, is cancelled and its queue slot freed (0: off).
  double upload_idle_seconds = 30.0;
  double upload_deadline_seconds = 600.0;
  // The result: a client that reads nothing of it for this long is cancelled and the output
  // mesh dropped (0: off).
  double result_idle_seconds = 60.0;
  // 0: off. Otherwise connections are closed (GOAWAY, running calls finish) after this long, so
  // that clients balancing over a headless Service re-resolve and find new replicas.
  double max_connection_age_seconds = 0.0;
  int retry_pushback_ms = 1000;     // suggested to clients when the queue is full
  size_t finished_jobs_kept = 256;  // for GetJob/ListJobs
  // gRPC server reflection (lists the services to any client): off unless asked for. Once on in
  // a process it stays on for every server started after (gRPC's library registers it globally
  // when loaded; FemsimpServer::Start loads it only for this).
  bool reflection = false;
  // Transport security (server/transport_security.h) and tenants (server/auth.h): empty is off.
  std::string tls_cert_file, tls_key_file, tls_client_ca_file;
  bool plaintext_remote = false;  // allow plaintext on an address reachable from the network
  std::string auth_tokens_file;
  int max_jobs_per_tenant = 0;  // unfinished (uploading, queued, running) jobs a tenant may have
};

// femsimp-server's flags (--listen, --workers, --threads_per_job, ...), storing into *c, with
// the ranges NormalizeConfig checks.
void AddServerFlags(flags::FlagSet& set, ServerConfig* c);

// Fills threads_per_job when 0 and clamps it to the host's cores; checks ranges.
std::string NormalizeConfig(ServerConfig* c);  // empty on success, else the problem

}  // namespace femsimp::server
