// femsimp-server: the gRPC simplification service.
#include <malloc.h>
#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <optional>
#include <string>

#include "common/flags.h"
#include "server/config.h"
#include "server/log.h"
#include "server/server.h"

constexpr char kUsage[] = R"(Usage: femsimp-server [flags]

Serves femsimp.v1.Simplifier over gRPC, with health, reflection and Prometheus metrics.
Flags take their value as `--flag VALUE` or `--flag=VALUE`.

)";
constexpr char kExitCodes[] = R"(
Exit codes: 0 stopped by a signal, 2 bad flags, 3 cannot listen.
)";

int main(int argc, char** argv) {
  // glibc raises its mmap threshold to the largest block freed (up to 32 MiB); from then on the
  // mesh-sized arrays come from the threads' heaps, which keep what is freed. A
  // fixed threshold keeps every block of 1 MiB or more mmapped and gives it back when freed:
  // peak RSS for the 1 M-face blade with the defaults 213 -> 155 MiB, the local CLI's 160 MiB
  // (docs/BENCHMARKS.md, "The service at engine speed").
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  femsimp::server::ServerConfig config;
  femsimp::flags::FlagSet flags("femsimp-server");
  femsimp::server::AddServerFlags(flags, &config);
  flags.AllowFlagfile();
  femsimp::flags::FlagSet::Parsed parsed;
  if (std::optional<int> exit = flags.ParseMain(argc, argv, kUsage, kExitCodes, &parsed))
    return *exit;
  std::string err = !parsed.positional.empty()
                        ? "unexpected argument '" + parsed.positional[0] + "'"
                        : femsimp::server::NormalizeConfig(&config);
  if (!err.empty()) {
    std::fprintf(stderr, "femsimp-server: %s\n", err.c_str());
    return femsimp::flags::kUsageExit;
  }

  // Signals go to one waiting thread (this one), not to whichever thread gRPC happens to run.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  femsimp::server::RouteProtobufLogs();
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
