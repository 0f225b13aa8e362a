#include "server/config.h"

#include <algorithm>
#include <thread>

#include "absl/strings/str_cat.h"
#include "common/range.h"
#include "server/memory_budget.h"

namespace femsimp::server {

namespace {

constexpr Range kWorkers = Range::AtLeast(1);
constexpr Range kNonNegative = Range::AtLeast(0);
constexpr Range kMaxVertices = Range::AtLeast(3);
constexpr Range kMaxFaces = Range::AtLeast(1);
constexpr Range kMaxRequestBytes = Range::AtLeast(64 << 10);
constexpr Range kMaxSpes = Range::Closed(1, 256);
constexpr Range kMaxCellMemory = Range::AtLeast(1);
constexpr Range kMemoryBudget = Range::AtLeast(0);

// "" when v is in r, else the flag's out-of-range message.
std::string Check(const char* flag, double v, const Range& r, const char* unit = "") {
  if (r.Contains(v)) return "";
  return std::string(flags::OutOfRange(flag, FormatNumber(v), r, unit).message());
}

}  // namespace

void AddServerFlags(flags::FlagSet& set, ServerConfig* c) {
  using flags::NumberKind;
  const ServerConfig d;  // the defaults, as ServerConfig has them
  set.String("--listen", "HOST:PORT", absl::StrCat("gRPC address (default ", d.listen, ")"),
             &c->listen);
  set.String("--tls_cert_file", "FILE",
             "serve TLS with this PEM certificate chain (with --tls_key_file)", &c->tls_cert_file);
  set.String("--tls_key_file", "FILE", "the PEM private key of --tls_cert_file", &c->tls_key_file);
  set.String("--tls_client_ca_file", "FILE",
             "mutual TLS: require client certificates signed by this PEM CA",
             &c->tls_client_ca_file);
  set.Switch("--plaintext_remote",
             "allow plaintext on an address reachable from the network (without TLS the server "
             "otherwise listens on loopback addresses only), e.g. behind a TLS-terminating proxy",
             &c->plaintext_remote);
  set.String("--auth_tokens_file", "FILE",
             "tenants by bearer token: CSV lines 'token,tenant' (Kubernetes static-token-file "
             "style); a call without a valid token gets UNAUTHENTICATED, a tenant sees only its "
             "own jobs",
             &c->auth_tokens_file);
  set.Number({.name = "--max_jobs_per_tenant",
              .metavar = "N",
              .help = "unfinished jobs (uploading, queued or running) one tenant may have; more "
                      "get RESOURCE_EXHAUSTED with a retry pushback (without tenants: all calls)",
              .kind = NumberKind::kInteger,
              .range = kNonNegative,
              .zero_means = "no limit",
              .default_text = FormatNumber(static_cast<double>(d.max_jobs_per_tenant))},
             &c->max_jobs_per_tenant);
  set.Switch("--reflection",
             "serve gRPC server reflection (lists the services to any client; default off)",
             &c->reflection);
  set.String(
      "--metrics_listen", "HOST:PORT",
      absl::StrCat("Prometheus /metrics address, empty: off (default ", d.metrics_listen, ")"),
      &c->metrics_listen);
  set.Number({.name = "--workers",
              .metavar = "N",
              .help = "jobs running at once",
              .kind = NumberKind::kInteger,
              .range = kWorkers,
              .default_text = FormatNumber(static_cast<double>(d.workers))},
             &c->workers);
  set.Number({.name = "--queue_capacity",
              .metavar = "N",
              .help = "jobs waiting or uploading at most; more get RESOURCE_EXHAUSTED",
              .kind = NumberKind::kInteger,
              .range = kNonNegative,
              .default_text = FormatNumber(static_cast<double>(d.queue_capacity))},
             &c->queue_capacity);
  set.Number({.name = "--threads_per_job",
              .metavar = "N",
              .help = "engine threads per job, at most the host's cores",
              .kind = NumberKind::kInteger,
              .range = kNonNegative,
              .zero_means = "cores / workers",
              .default_text = FormatNumber(static_cast<double>(d.threads_per_job))},
             &c->threads_per_job);
  set.Number({.name = "--max_vertices",
              .metavar = "N",
              .help = "largest accepted mesh, in vertices",
              .kind = NumberKind::kInteger,
              .range = kMaxVertices,
              .default_text = FormatNumber(static_cast<double>(d.max_vertices))},
             &c->max_vertices);
  set.Number({.name = "--max_faces",
              .metavar = "N",
              .help = "largest accepted mesh, in faces",
              .kind = NumberKind::kInteger,
              .range = kMaxFaces,
              .default_text = FormatNumber(static_cast<double>(d.max_faces))},
             &c->max_faces);
  set.Number({.name = "--max_request_bytes",
              .metavar = "N",
              .help = "largest accepted request message",
              .kind = NumberKind::kInteger,
              .range = kMaxRequestBytes,
              .unit = "bytes",
              .default_text = FormatNumber(static_cast<double>(d.max_request_bytes))},
             &c->max_request_bytes);
  set.Number({.name = "--memory_budget_mib",
              .metavar = "N",
              .help = "admit a job only while the estimated peak memory of the admitted jobs "
                      "(from their declared vertex and face counts) stays within N MiB; a job "
                      "that does not fit beside them gets RESOURCE_EXHAUSTED with a retry "
                      "pushback, one above N alone RESOURCE_EXHAUSTED without",
              .kind = NumberKind::kInteger,
              .range = kMemoryBudget,
              .unit = "MiB",
              .zero_means = "3/4 of the memory the server may use (physical or cgroup limit)",
              .default_text = "0"},
             &c->memory_budget_mib);
  set.Number({.name = "--max_spes",
              .metavar = "N",
              .help = "most SPEs a cell back-end job may ask for (each is a host thread)",
              .kind = NumberKind::kInteger,
              .range = kMaxSpes,
              .default_text = FormatNumber(static_cast<double>(d.max_spes))},
             &c->max_spes);
  set.Number({.name = "--max_cell_local_store_mib",
              .metavar = "N",
              .help = "most emulated local store a cell back-end job may ask for, over its SPEs",
              .kind = NumberKind::kInteger,
              .range = kMaxCellMemory,
              .unit = "MiB",
              .default_text = FormatNumber(static_cast<double>(d.max_cell_local_store_mib))},
             &c->max_cell_local_store_mib);
  set.Number({.name = "--grace_period_seconds",
              .metavar = "S",
              .help = "on SIGTERM/SIGINT, time running jobs get to finish before they are "
                      "cancelled",
              .range = kNonNegative,
              .unit = "seconds",
              .default_text = FormatNumber(static_cast<double>(d.grace_period_seconds))},
             &c->grace_period_seconds);
  set.Number({.name = "--upload_idle_seconds",
              .metavar = "S",
              .help = "cancel an upload (spec and mesh chunks) that sends nothing for this long, "
                      "freeing its queue slot",
              .range = kNonNegative,
              .unit = "seconds",
              .zero_means = "never",
              .default_text = FormatNumber(d.upload_idle_seconds)},
             &c->upload_idle_seconds);
  set.Number({.name = "--upload_deadline_seconds",
              .metavar = "S",
              .help = "cancel an upload not done after this long in all",
              .range = kNonNegative,
              .unit = "seconds",
              .zero_means = "never",
              .default_text = FormatNumber(d.upload_deadline_seconds)},
             &c->upload_deadline_seconds);
  set.Number({.name = "--result_idle_seconds",
              .metavar = "S",
              .help = "cancel a call whose client reads nothing of its result for this long, "
                      "dropping the output mesh",
              .range = kNonNegative,
              .unit = "seconds",
              .zero_means = "never",
              .default_text = FormatNumber(d.result_idle_seconds)},
             &c->result_idle_seconds);
  set.Number({.name = "--max_connection_age_seconds",
              .metavar = "S",
              .help = "close client connections after this long (running calls finish first), "
                      "so clients balancing over DNS re-resolve and find new replicas",
              .range = kNonNegative,
              .unit = "seconds",
              .zero_means = "never",
              .default_text = FormatNumber(static_cast<double>(d.max_connection_age_seconds))},
             &c->max_connection_age_seconds);
}

std::string NormalizeConfig(ServerConfig* c) {
  for (const std::string& err :
       {Check("--workers", c->workers, kWorkers),
        Check("--queue_capacity", c->queue_capacity, kNonNegative),
        Check("--threads_per_job", c->threads_per_job, kNonNegative),
        Check("--max_vertices", static_cast<double>(c->max_vertices), kMaxVertices),
        Check("--max_faces", static_cast<double>(c->max_faces), kMaxFaces),
        Check("--max_request_bytes", static_cast<double>(c->max_request_bytes), kMaxRequestBytes,
              "bytes"),
        Check("--max_spes", c->max_spes, kMaxSpes),
        Check("--max_cell_local_store_mib", c->max_cell_local_store_mib, kMaxCellMemory, "MiB"),
        Check("--grace_period_seconds", c->grace_period_seconds, kNonNegative, "seconds"),
        Check("--max_connection_age_seconds", c->max_connection_age_seconds, kNonNegative,
              "seconds"),
        Check("--upload_idle_seconds", c->upload_idle_seconds, kNonNegative, "seconds"),
        Check("--upload_deadline_seconds", c->upload_deadline_seconds, kNonNegative, "seconds"),
        Check("--result_idle_seconds", c->result_idle_seconds, kNonNegative, "seconds")})
    if (!err.empty()) return err;
  int cores = std::max(1u, std::thread::hardware_concurrency());
  // More threads than cores only adds contention to a shared-memory pass.
  if (c->threads_per_job == 0) c->threads_per_job = std::max(1, cores / c->workers);
  c->threads_per_job = std::min(c->threads_per_job, cores);
  if (c->memory_budget_mib == 0) c->memory_budget_mib = AvailableMemoryBytes() / 4 * 3 >> 20;
  if (c->memory_budget_mib == 0)
    return "--memory_budget_mib: cannot read this machine's memory; set it";
  return "";
}

}  // namespace femsimp::server
