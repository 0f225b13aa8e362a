// femsimp-load: C concurrent clients sending Simplify jobs to a server; reports throughput,
// latency percentiles and errors by status code.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/args.h"
#include "client/exit_codes.h"
#include "client/remote_call.h"
#include "engine/io/mesh_io.h"
#include "proto/wire.h"

namespace {

using namespace femsimp;
using namespace femsimp::cli;

constexpr char kUsage[] =
    R"(Usage: femsimp-load --server HOST:PORT --clients C (--jobs N | --duration S)
                    [--ratio R] [--threads N] [--deadline S] [--json] MESH...

Runs C concurrent clients, each sending one Simplify job after the other (meshes taken in turn),
until N jobs were sent in all (--jobs) or S seconds passed (--duration). Prints jobs/s, latency
p50/p95/p99 of successful jobs and the errors by gRPC status code; --json prints the same as JSON.

  --server HOST:PORT   femsimp-server to load
  --clients C          concurrent clients (each its own channel), in [1, 1024]
  --jobs N             total jobs, in [1, 10000000]
  --duration S         seconds to keep sending (jobs in flight at the end are awaited)
  --ratio R            target ratio of every job (default 0.5)
  --threads N          engine threads per job (default: the server's)
  --deadline S         per-job deadline in seconds (default: none)
  --json               JSON report on stdout instead of text

Exit codes: 0 every job succeeded, 1 some jobs failed, 2 usage error, 3 a mesh file unreadable.
)";

struct Config {
  std::string server;
  int clients = 0;
  long long jobs = 0;
  double duration = 0;
  double ratio = 0.5;
  int threads = 0;
  double deadline = 0;
  bool json = false;
  std::vector<std::string> meshes;
};

absl::StatusOr<Config> Parse(const std::vector<std::string>& args) {
  Config c;
  for (size_t i = 1; i < args.size(); ++i) {
    std::string a = args[i], value;
    if (a == "--json") {
      c.json = true;
      continue;
    }
    if (a.rfind("--", 0) != 0) {
      c.meshes.push_back(a);
      continue;
    }
    if (size_t eq = a.find('='); eq != std::string::npos) {
      value = a.substr(eq + 1);
      a = a.substr(0, eq);
    } else {
      if (i + 1 >= args.size())
        return absl::InvalidArgumentError(absl::StrCat(a, " needs a value"));
      value = args[++i];
    }
    if (a == "--server") {
      c.server = value;
    } else if (a == "--clients") {
      absl::StatusOr<long long> v = ParseInt(a, value, 1, 1024);
      if (!v.ok()) return v.status();
      c.clients = static_cast<int>(*v);
    } else if (a == "--jobs") {
      absl::StatusOr<long long> v = ParseInt(a, value, 1, 10'000'000);
      if (!v.ok()) return v.status();
      c.jobs = *v;
    } else if (a == "--duration" || a == "--ratio" || a == "--deadline") {
      absl::StatusOr<double> v = ParseDouble(a, value);
      if (!v.ok()) return v.status();
      if (a == "--ratio") {
        if (*v < 0 || *v >= 1)
          return absl::InvalidArgumentError("--ratio is out of range: must be in [0, 1)");
        c.ratio = *v;
      } else {
        if (*v <= 0) return absl::InvalidArgumentError(absl::StrCat(a, " must be > 0"));
        (a == "--duration" ? c.duration : c.deadline) = *v;
      }
    } else if (a == "--threads") {
      absl::StatusOr<long long> v = ParseInt(a, value, 1, 1024);
      if (!v.ok()) return v.status();
      c.threads = static_cast<int>(*v);
    } else {
      return absl::InvalidArgumentError(absl::StrCat("unknown option '", a, "'"));
    }
  }
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

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv, argv + argc);
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      return kExitOk;
    }
  absl::StatusOr<Config> cfg = Parse(args);
  if (!cfg.ok()) {
    std::fprintf(stderr, "femsimp-load: %s (see --help)\n",
                 std::string(cfg.status().message()).c_str());
    return kExitUsage;
  }
  std::vector<RawMesh> meshes;
  for (const std::string& path : cfg->meshes) {
    absl::StatusOr<RawMesh> m = ReadMeshFile(path);
    if (!m.ok()) {
      std::fprintf(stderr, "femsimp-load: cannot read %s: %s\n", path.c_str(),
                   std::string(m.status().message()).c_str());
      return kExitInputUnreadable;
    }
    meshes.push_back(std::move(*m));
  }

  SimplifyOptions options;
  options.ratio = cfg->ratio;
  options.threads = std::max(1, cfg->threads);
  v1::JobSpec spec;
  wire::ToProto(options, cfg->threads > 0, spec.mutable_options());

  std::atomic<long long> next{0};
  std::mutex mu;
  std::vector<double> ok_latency;
  std::map<std::string, long long> errors;
  std::map<std::string, std::string> error_examples;
  const auto start = std::chrono::steady_clock::now();
  const auto stop_at = start + std::chrono::duration<double>(cfg->duration);
  auto more = [&](long long* index) {
    if (cfg->jobs > 0) {
      *index = next.fetch_add(1);
      return *index < cfg->jobs;
    }
    *index = next.fetch_add(1);
    return std::chrono::steady_clock::now() < stop_at;
  };
  std::vector<std::thread> clients;
  for (int c = 0; c < cfg->clients; ++c) {
    clients.emplace_back([&, c] {
      // One channel (connection) per client, like separate client processes.
      auto stub = v1::Simplifier::NewStub(MakeChannel(cfg->server, c));
      long long index;
      while (more(&index)) {
        const RawMesh& mesh = meshes[static_cast<size_t>(index) % meshes.size()];
        grpc::ClientContext ctx;
        if (cfg->deadline > 0)
          ctx.set_deadline(std::chrono::system_clock::now() +
                           std::chrono::microseconds(static_cast<int64_t>(cfg->deadline * 1e6)));
        auto t0 = std::chrono::steady_clock::now();
        RemoteOutcome out = RemoteSimplify(*stub, ctx, spec, mesh, {}, /*keep_output=*/false);
        double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::lock_guard<std::mutex> lock(mu);
        if (out.status.ok()) {
          ok_latency.push_back(seconds);
        } else {
          std::string name = GrpcCodeName(out.status.error_code());
          ++errors[name];
          error_examples.emplace(name, out.status.error_message());
        }
      }
    });
  }
  for (std::thread& t : clients) t.join();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  long long failed = 0;
  for (const auto& [name, n] : errors) failed += n;
  const long long total = static_cast<long long>(ok_latency.size()) + failed;
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
        "%lld, \"wall_seconds\": %.6f, \"jobs_per_second\": %.6f, \"latency_seconds\": "
        "{\"p50\": %.6f, \"p95\": %.6f, \"p99\": %.6f}, \"errors\": %s}\n",
        cfg->server.c_str(), cfg->clients, total, ok_latency.size(), failed, wall, rate, p50, p95,
        p99, e.c_str());
  } else {
    std::printf("server %s, %d clients, %lld jobs in %.2f s\n", cfg->server.c_str(), cfg->clients,
                total, wall);
    std::printf("succeeded %zu, failed %lld, throughput %.2f jobs/s\n", ok_latency.size(), failed,
                rate);
    std::printf("latency p50 %.3f s, p95 %.3f s, p99 %.3f s\n", p50, p95, p99);
    for (const auto& [name, n] : errors)
      std::printf("errors %s: %lld (e.g. \"%s\")\n", name.c_str(), n, error_examples[name].c_str());
  }
  return failed == 0 ? kExitOk : kExitInternal;
}
