// femsimp-load: C concurrent clients sending Simplify jobs to a server; reports throughput,
// latency percentiles, errors by status code, and retries (a job that fails with UNAVAILABLE or
// a pushed-back RESOURCE_EXHAUSTED is sent again, client/retry.h).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/args.h"
#include "client/channel_security.h"
#include "client/exit_codes.h"
#include "client/remote_call.h"
#include "client/retry.h"
#include "common/escape.h"
#include "common/flags.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh_checks.h"
#include "engine/option_flags.h"
#include "proto/wire.h"

namespace {

using namespace femsimp;
using namespace femsimp::cli;

struct Config {
  std::string server;
  int clients = 0;
  long long jobs = 0;
  double duration = 0;
  double rate = 0;          // jobs started per second at most; 0: no limit
  SimplifyOptions options;  // ratio and threads (given or not)
  bool threads_given = false;
  double deadline = 0;
  int max_attempts = 5;
  bool verify = false;
  std::string jobs_report;
  bool json = false;
  std::vector<std::string> meshes;
  SecurityFlags security;
};

flags::FlagSet LoadFlags(Config* c) {
  flags::FlagSet set("femsimp-load");
  set.Value("--server", "HOST:PORT", "femsimp-server to load",
            ServerAddressSetter("--server", &c->server));
  AddSecurityFlags(set, &c->security);
  set.Number({.name = "--clients",
              .metavar = "C",
              .help = "concurrent clients (each its own channel)",
              .kind = flags::NumberKind::kInteger,
              .range = Range::Closed(1, 1024)},
             &c->clients);
  set.Number({.name = "--jobs",
              .metavar = "N",
              .help = "total jobs",
              .kind = flags::NumberKind::kInteger,
              .range = Range::Closed(1, 10'000'000)},
             &c->jobs);
  set.Number({.name = "--duration",
              .metavar = "S",
              .help = "time to keep sending (jobs in flight at the end are awaited)",
              .range = Range::Above(0),
              .unit = "seconds"},
             &c->duration);
  set.Number({.name = "--rate",
              .metavar = "J",
              .help = "start at most J jobs per second in all (job i not before i / J s), so a "
                      "run lasts as long on any machine that keeps up",
              .range = Range::Above(0),
              .default_text = "as fast as the clients go"},
             &c->rate);
  AddOptionFlag(set, "ratio", &c->options, "0.5");
  AddOptionFlag(set, "threads", &c->options, "the server's");
  set.Number({.name = "--deadline",
              .metavar = "S",
              .help = "per-job deadline, all attempts together",
              .range = Range::Above(0),
              .unit = "seconds",
              .default_text = "none"},
             &c->deadline);
  set.Number({.name = "--max-attempts",
              .metavar = "A",
              .help = "calls per job, retries included",
              .kind = flags::NumberKind::kInteger,
              .range = Range::Closed(1, 100),
              .default_text = "5"},
             &c->max_attempts);
  set.Switch("--verify",
             "assemble every result and check it: a valid mesh (manifold, oriented, no "
             "degenerate face) with the input's Euler characteristic, components and closedness; "
             "a failed check counts as error INVALID_OUTPUT",
             &c->verify);
  set.String("--jobs-report", "FILE",
             "one line per job: index, mesh, status, attempts, job id, output vertices and "
             "faces, seconds (tab-separated, with a header)",
             &c->jobs_report);
  set.Switch("--json", "JSON report on stdout instead of text", &c->json);
  return set;
}

std::string Usage() {
  Config unused;
  return absl::StrCat(
      R"(Usage: femsimp-load --server HOST:PORT --clients C (--jobs N | --duration S)
                    [--ratio R] [--threads N] [--deadline S] [--rate J] [--max-attempts A]
                    [--verify] [--jobs-report FILE] [--json] MESH...

Runs C concurrent clients, each sending one Simplify job after the other (meshes taken in turn),
until N jobs were sent in all (--jobs) or S seconds passed (--duration). Prints jobs/s, latency
p50/p95/p99 of successful jobs, the errors by gRPC status code, the attempts and retries, and
the jobs lost (sent but without a whole result); --json prints the same as JSON.

A job that fails with UNAVAILABLE (server or replica gone) or RESOURCE_EXHAUSTED with a retry
pushback (queue full) is sent again as a new call, after the pushback or a backoff (0.25 s
doubling up to 8 s, +-20 %). A job counts as done only once its result and every mesh chunk
arrived and add up.

)",
      LoadFlags(&unused).Help(), R"(
Exit codes: 0 every job succeeded, 1 some jobs failed or were lost, 2 usage error,
3 a mesh file unreadable, 5 --jobs-report could not be written.
)");
}

// Parsed (help: Usage() in help_text, nothing else checked).
absl::StatusOr<Config> Parse(const std::vector<std::string>& args, bool* help) {
  Config c;
  c.options.ratio = 0.5;
  absl::StatusOr<flags::FlagSet::Parsed> parsed = LoadFlags(&c).Parse(args);
  if (!parsed.ok()) return parsed.status();
  *help = parsed->help;
  if (*help) return c;
  c.meshes = parsed->positional;
  c.threads_given = parsed->Given("--threads");
  if (c.server.empty()) return absl::InvalidArgumentError("--server is required");
  if (c.clients == 0) return absl::InvalidArgumentError("--clients is required");
  if ((c.jobs > 0) == (c.duration > 0))
    return absl::InvalidArgumentError("give exactly one of --jobs and --duration");
  if (c.meshes.empty()) return absl::InvalidArgumentError("no MESH files given");
  return c;
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  size_t i = static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

// What became of one job, for the totals and --jobs-report.
struct JobRecord {
  long long index = 0;
  size_t mesh = 0;
  std::string status;  // "OK", a gRPC code name, or INVALID_OUTPUT
  std::string message;
  int attempts = 0;
  std::string job_id;
  uint64_t output_vertices = 0, output_faces = 0;
  double seconds = 0;
};

absl::Status WriteJobsReport(const std::string& path, std::vector<JobRecord> records,
                             const std::vector<std::string>& meshes) {
  std::sort(records.begin(), records.end(),
            [](const JobRecord& a, const JobRecord& b) { return a.index < b.index; });
  std::ofstream f(path, std::ios::trunc);
  if (!f) return absl::PermissionDeniedError(absl::StrCat(path, ": cannot open for writing"));
  f << "index\tmesh\tstatus\tattempts\tjob_id\toutput_vertices\toutput_faces\tseconds\n";
  for (const JobRecord& r : records)
    f << absl::StrFormat("%d\t%s\t%s\t%d\t%s\t%u\t%u\t%.6f\n", r.index, meshes[r.mesh], r.status,
                         r.attempts, r.job_id.empty() ? "-" : r.job_id, r.output_vertices,
                         r.output_faces, r.seconds);
  f.close();
  if (!f) return absl::DataLossError(absl::StrCat(path, ": write failed"));
  return absl::OkStatus();
}

}  // namespace

int main(int argc, char** argv) {
  bool help = false;
  absl::StatusOr<Config> cfg = Parse(std::vector<std::string>(argv + 1, argv + argc), &help);
  if (help) {
    std::fputs(Usage().c_str(), stdout);
    return kExitOk;
  }
  if (!cfg.ok()) {
    PrintError("femsimp-load: %s (see --help)\n", std::string(cfg.status().message()).c_str());
    return kExitUsage;
  }
  absl::StatusOr<ChannelSecurity> security = ResolveSecurity(cfg->security);
  if (!security.ok()) {
    PrintError("femsimp-load: %s\n", std::string(security.status().message()).c_str());
    return kExitUsage;
  }
  std::vector<RawMesh> meshes;
  std::vector<SoupTopology> topologies;
  for (const std::string& path : cfg->meshes) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    if (!m.ok()) {
      PrintError("femsimp-load: cannot read %s: %s\n", path.c_str(),
                 EscapeControlCharacters(std::string(m.status().message())).c_str());
      return kExitInputUnreadable;
    }
    topologies.push_back(TopologyOf(*m));
    meshes.push_back(std::move(*m));
  }

  v1::JobSpec spec;
  wire::ToProto(cfg->options, cfg->threads_given, spec.mutable_options());

  std::atomic<long long> next{0};
  std::mutex mu;
  std::vector<double> ok_latency;
  std::map<std::string, long long> errors;
  std::map<std::string, std::string> error_examples;
  std::vector<JobRecord> records;
  RetryCounters retry_totals;
  long long retried_jobs = 0;
  const auto start = std::chrono::steady_clock::now();
  const auto stop_at = start + std::chrono::duration<double>(cfg->duration);
  auto more = [&](long long* index) {
    *index = next.fetch_add(1);
    if (cfg->jobs > 0 && *index >= cfg->jobs) return false;
    if (cfg->rate > 0)
      std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                std::chrono::duration<double>(*index / cfg->rate)));
    return cfg->jobs > 0 || std::chrono::steady_clock::now() < stop_at;
  };
  std::vector<std::thread> clients;
  for (int c = 0; c < cfg->clients; ++c) {
    clients.emplace_back([&, c] {
      // One channel (connection) per client, like separate client processes.
      std::shared_ptr<grpc::Channel> channel = MakeChannel(cfg->server, *security, c);
      auto stub = v1::Simplifier::NewStub(channel);
      long long index;
      while (more(&index)) {
        JobRecord rec;
        rec.index = index;
        rec.mesh = static_cast<size_t>(index) % meshes.size();
        RetryOptions retry;
        retry.channel = channel;
        retry.policy.max_attempts = cfg->max_attempts;
        retry.keep_output = cfg->verify;
        if (cfg->deadline > 0)
          retry.deadline = std::chrono::system_clock::now() +
                           std::chrono::microseconds(static_cast<int64_t>(cfg->deadline * 1e6));
        RetryCounters counters;
        auto t0 = std::chrono::steady_clock::now();
        RemoteOutcome out = SimplifyWithRetry(*stub, spec, meshes[rec.mesh], retry, &counters);
        rec.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        rec.attempts = counters.attempts;
        rec.status = GrpcCodeName(out.status.error_code());
        rec.message = out.status.error_message();
        if (out.status.ok()) {
          rec.job_id = out.result.job_id();
          rec.output_vertices = out.result.output_vertices();
          rec.output_faces = out.result.output_faces();
          if (cfg->verify) {
            if (absl::Status v = CheckOutput(topologies[rec.mesh], out.output); !v.ok()) {
              rec.status = "INVALID_OUTPUT";
              rec.message = absl::StrCat("job ", rec.job_id, ": ", v.message());
            }
          }
        }
        std::lock_guard<std::mutex> lock(mu);
        retry_totals.attempts += counters.attempts;
        retry_totals.unavailable += counters.unavailable;
        retry_totals.resource_exhausted += counters.resource_exhausted;
        retry_totals.waited_seconds += counters.waited_seconds;
        if (counters.attempts > 1) ++retried_jobs;
        if (rec.status == "OK") {
          ok_latency.push_back(rec.seconds);
        } else {
          ++errors[rec.status];
          error_examples.emplace(rec.status, rec.message);
        }
        records.push_back(std::move(rec));
      }
    });
  }
  for (std::thread& t : clients) t.join();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Every job sent has exactly one record; count it again from the records so that a job lost
  // or reported twice would show.
  const long long sent = cfg->jobs > 0 ? cfg->jobs : static_cast<long long>(records.size());
  std::map<long long, int> done_per_index;
  for (const JobRecord& r : records)
    if (r.status == "OK") ++done_per_index[r.index];
  long long duplicates = 0;
  for (const auto& [index, n] : done_per_index) duplicates += n - 1;
  const long long lost = sent - static_cast<long long>(done_per_index.size());

  long long failed = 0;
  for (const auto& [name, n] : errors) failed += n;
  const long long total = static_cast<long long>(ok_latency.size()) + failed;
  const long long retries = retry_totals.attempts - total;
  const double rate = wall > 0 ? static_cast<double>(ok_latency.size()) / wall : 0;
  const double p50 = Percentile(ok_latency, 0.50), p95 = Percentile(ok_latency, 0.95),
               p99 = Percentile(ok_latency, 0.99);
  if (cfg->json) {
    std::string e = "{";
    bool first = true;
    for (const auto& [name, n] : errors) {
      absl::StrAppend(&e, first ? "" : ", ", "\"", name, "\": ", n);
      first = false;
    }
    e += "}";
    std::printf(
        "{\"server\": \"%s\", \"clients\": %d, \"jobs\": %lld, \"succeeded\": %zu, \"failed\": "
        "%lld, \"lost\": %lld, \"duplicates\": %lld, \"verified\": %s, \"wall_seconds\": %.6f, "
        "\"jobs_per_second\": %.6f, \"latency_seconds\": {\"p50\": %.6f, \"p95\": %.6f, "
        "\"p99\": %.6f}, \"attempts\": %d, \"retries\": %lld, \"retried_jobs\": %lld, "
        "\"failed_attempts\": {\"UNAVAILABLE\": %d, \"RESOURCE_EXHAUSTED\": %d}, "
        "\"retry_wait_seconds\": %.3f, \"errors\": %s}\n",
        cfg->server.c_str(), cfg->clients, total, ok_latency.size(), failed, lost, duplicates,
        cfg->verify ? "true" : "false", wall, rate, p50, p95, p99, retry_totals.attempts, retries,
        retried_jobs, retry_totals.unavailable, retry_totals.resource_exhausted,
        retry_totals.waited_seconds, e.c_str());
  } else {
    std::printf("server %s, %d clients, %lld jobs in %.2f s\n", cfg->server.c_str(), cfg->clients,
                total, wall);
    std::printf(
        "succeeded %zu%s, failed %lld, lost %lld, duplicates %lld, throughput %.2f jobs/s\n",
        ok_latency.size(), cfg->verify ? " (verified)" : "", failed, lost, duplicates, rate);
    std::printf("latency p50 %.3f s, p95 %.3f s, p99 %.3f s\n", p50, p95, p99);
    std::printf(
        "attempts %d, retries %lld (%lld jobs retried; failed attempts: UNAVAILABLE %d, "
        "RESOURCE_EXHAUSTED %d; %.1f s waited)\n",
        retry_totals.attempts, retries, retried_jobs, retry_totals.unavailable,
        retry_totals.resource_exhausted, retry_totals.waited_seconds);
    for (const auto& [name, n] : errors)
      std::printf("errors %s: %lld (e.g. \"%s\")\n", name.c_str(), n, error_examples[name].c_str());
  }
  if (!cfg->jobs_report.empty()) {
    if (absl::Status w = WriteJobsReport(cfg->jobs_report, records, cfg->meshes); !w.ok()) {
      PrintError("femsimp-load: --jobs-report: %s\n", std::string(w.message()).c_str());
      return kExitOutputFailed;
    }
  }
  return failed == 0 && lost == 0 && duplicates == 0 ? kExitOk : kExitInternal;
}
