#include "client/health.h"
#include "common/escape.h"

#include <chrono>
#include <cstdio>

#include "absl/strings/str_cat.h"
#include "client/args.h"
#include "client/channel_security.h"
#include "client/exit_codes.h"
#include "client/remote_call.h"
#include "common/flags.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace femsimp::cli {

namespace {

flags::FlagSet HealthFlags(HealthArgs* h) {
  flags::FlagSet set("femsimp health");
  set.Value("--server", "HOST:PORT", "the server (or a load balancer in front of replicas)",
            ServerAddressSetter("--server", &h->server));
  AddSecurityFlags(set, &h->security);
  set.String("--service", "NAME",
             "a single service, e.g. femsimp.v1.Simplifier (default: the whole server)",
             &h->service);
  set.Number({.name = "--timeout",
              .metavar = "SECONDS",
              .help = "give up after SECONDS",
              .range = Range::Above(0),
              .unit = "seconds",
              .default_text = "5"},
             &h->timeout_seconds);
  return set;
}

}  // namespace

std::string HealthUsage() {
  HealthArgs unused;
  return absl::StrCat(
      R"(Usage: femsimp health --server HOST:PORT [--service NAME] [--timeout SECONDS]

Asks the server's gRPC health service (grpc.health.v1.Health/Check) whether it is serving and
prints the answer. femsimp-server answers SERVING while it accepts jobs and NOT_SERVING from
SIGTERM on (while it drains). The container image uses this as its HEALTHCHECK.

)",
      HealthFlags(&unused).Help(), R"(
Exit codes: 0 SERVING, 2 usage error, 8 the server answered but is not SERVING,
20+N the call failed with gRPC status N (24 DEADLINE_EXCEEDED, 25 NOT_FOUND: unknown service,
34 UNAVAILABLE: not reachable).
)");
}

absl::StatusOr<HealthArgs> ParseHealthArgs(const std::vector<std::string>& args) {
  HealthArgs h;
  absl::StatusOr<flags::FlagSet::Parsed> parsed = HealthFlags(&h).Parse(args);
  if (!parsed.ok()) return parsed.status();
  h.help = parsed->help;
  if (h.help) return h;
  if (!parsed->positional.empty())
    return absl::InvalidArgumentError(
        absl::StrCat("unknown argument '", parsed->positional[0], "' (see femsimp health --help)"));
  if (h.server.empty()) return absl::InvalidArgumentError("health needs --server HOST:PORT");
  return h;
}

HealthOutcome CheckHealth(const HealthArgs& args) {
  HealthOutcome out;
  absl::StatusOr<ChannelSecurity> security = ResolveSecurity(args.security);
  if (!security.ok()) {
    out.status =
        grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, std::string(security.status().message()));
    return out;
  }
  auto stub = grpc::health::v1::Health::NewStub(MakeChannel(args.server, *security));
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() +
                   std::chrono::microseconds(static_cast<int64_t>(args.timeout_seconds * 1e6)));
  grpc::health::v1::HealthCheckRequest req;
  req.set_service(args.service);
  grpc::health::v1::HealthCheckResponse resp;
  out.status = stub->Check(&ctx, req, &resp);
  if (out.status.ok())
    out.serving_status = grpc::health::v1::HealthCheckResponse::ServingStatus_Name(resp.status());
  return out;
}

int RunHealth(const std::vector<std::string>& args) {
  absl::StatusOr<HealthArgs> h = ParseHealthArgs(args);
  if (!h.ok()) {
    PrintError("femsimp: %s\n", std::string(h.status().message()).c_str());
    return kExitUsage;
  }
  if (h->help) {
    std::fputs(HealthUsage().c_str(), stdout);
    return kExitOk;
  }
  HealthOutcome out = CheckHealth(*h);
  const std::string what =
      h->service.empty() ? h->server : absl::StrCat(h->server, " ", h->service);
  if (!out.status.ok()) {
    grpc::StatusCode code = out.status.error_code();
    PrintError("femsimp: health of %s: %s (%s: %s)\n", what.c_str(),
               code == grpc::StatusCode::NOT_FOUND ? "the server knows no such service"
                                                   : GrpcCodeHint(code),
               GrpcCodeName(code), out.status.error_message().c_str());
    return kExitGrpcBase + static_cast<int>(code);
  }
  std::printf("%s: %s\n", what.c_str(), out.serving_status.c_str());
  return out.serving() ? kExitOk : kExitNotServing;
}

}  // namespace femsimp::cli
