// `femsimp health`: one Check call to a server's standard gRPC health service (grpc.health.v1).
// It is the container image's HEALTHCHECK; Kubernetes probes the same service natively.
#pragma once

#include <string>

#include <vector>
#include "client/security_flags.h"

#include "absl/status/statusor.h"
#include "grpcpp/support/status.h"

namespace femsimp::cli {

struct HealthArgs {
  std::string server;   // HOST:PORT
  std::string service;  // "" asks for the server as a whole
  double timeout_seconds = 5.0;
  bool help = false;
  SecurityFlags security;
};

std::string HealthUsage();
// The arguments after "health". Errors name the flag and the problem (a usage error).
absl::StatusOr<HealthArgs> ParseHealthArgs(const std::vector<std::string>& args);

struct HealthOutcome {
  grpc::Status status;         // of the Check call
  std::string serving_status;  // "SERVING", "NOT_SERVING", ... when the call succeeded
  bool serving() const { return status.ok() && serving_status == "SERVING"; }
};

HealthOutcome CheckHealth(const HealthArgs& args);

// Parses, checks, prints the serving status (or why there is none); returns the exit code:
// 0 SERVING, 8 answered but not SERVING, 2 usage error, 20 + the gRPC code when the call failed.
int RunHealth(const std::vector<std::string>& args);

}  // namespace femsimp::cli
