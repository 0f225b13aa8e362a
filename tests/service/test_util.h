// Helpers of the service tests: an in-process server, raw request streams, a minimal HTTP GET
// for /metrics. The meshes come from tests/support.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "client/remote_call.h"
#include "engine/raw_mesh.h"
#include "femsimp/v1/femsimp.grpc.pb.h"
#include "server/server.h"
#include "tests/support/meshes.h"

namespace femsimp::testing {

// Listens on free loopback ports; small limits the tests can reach.
server::ServerConfig TestConfig();

class InProcessServer {
 public:
  explicit InProcessServer(server::ServerConfig config = TestConfig());
  ~InProcessServer();
  std::string address() const;
  v1::Simplifier::Stub& stub() { return *stub_; }
  server::FemsimpServer& server() { return *server_; }

 private:
  std::unique_ptr<server::FemsimpServer> server_;
  std::unique_ptr<v1::Simplifier::Stub> stub_;
};

v1::JobSpec RatioSpec(double ratio, int threads = 0);

// One worker with one context, so that "the next job runs" shows that a job let go of it.
server::ServerConfig OneWorkerConfig();
// The server is whole after a job ended: nothing running, and the next job (fandisk) runs.
void ExpectWorkerFree(InProcessServer& s);

// GetJob; nullopt when the call fails (unknown job).
std::optional<v1::JobInfo> GetJob(v1::Simplifier::Stub& stub, const std::string& id);
// Polls GetJob every 2 ms while the job is in `state`; the job as last seen, nullopt when it is
// unknown or still in `state` after the timeout.
std::optional<v1::JobInfo> WaitWhile(v1::Simplifier::Stub& stub, const std::string& id,
                                     v1::JobState state, double timeout_seconds = 60);

// Sends exactly these requests, half-closes, reads to the end; the call's status.
grpc::Status SendRaw(v1::Simplifier::Stub& stub, const std::vector<v1::SimplifyRequest>& requests);

// GET http://127.0.0.1:port/path; the body ("" on failure).
std::string HttpGet(int port, const std::string& path);
// A TCP connection to 127.0.0.1:port (-1 on failure), and one whole HTTP exchange on a new one
// (what came back, status line and headers included; empty on failure).
int ConnectLoopback(int port);
std::string HttpExchange(int port, const std::string& request);
// Prometheus text format: "name{labels}" -> value, comments skipped.
std::map<std::string, double> ParseMetrics(const std::string& text);

int FreePort();

}  // namespace femsimp::testing
