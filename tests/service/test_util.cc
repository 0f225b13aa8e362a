#include "tests/service/test_util.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <thread>

#include "absl/strings/str_cat.h"
#include "engine/io/mesh_io.h"
#include "gtest/gtest.h"

namespace femsimp::testing {

server::ServerConfig TestConfig() {
  server::ServerConfig c;
  c.listen = "127.0.0.1:0";
  c.metrics_listen = "127.0.0.1:0";
  c.workers = 2;
  c.queue_capacity = 16;
  c.threads_per_job = 2;
  c.grace_period_seconds = 5;
  c.retry_pushback_ms = 250;
  return c;
}

InProcessServer::InProcessServer(server::ServerConfig config)
    : server_(std::make_unique<server::FemsimpServer>(std::move(config))) {
  absl::Status s = server_->Start();
  EXPECT_TRUE(s.ok()) << s;
  stub_ = v1::Simplifier::NewStub(cli::MakeChannel(address()));
}

InProcessServer::~InProcessServer() { server_->Shutdown(); }

std::string InProcessServer::address() const { return absl::StrCat("127.0.0.1:", server_->port()); }

v1::JobSpec RatioSpec(double ratio, int threads) {
  v1::JobSpec spec;
  // The service tests time the service, not the fidelity rules: the paper's criteria alone
  // reach any ratio fast.
  spec.mutable_options()->set_preset(v1::PRESET_PAPER);
  spec.mutable_options()->set_ratio(ratio);
  spec.mutable_options()->set_threads(threads);
  spec.set_client_label("test");
  return spec;
}

std::optional<v1::JobInfo> GetJob(v1::Simplifier::Stub& stub, const std::string& id) {
  grpc::ClientContext ctx;
  v1::GetJobRequest req;
  req.set_job_id(id);
  v1::JobInfo info;
  if (!stub.GetJob(&ctx, req, &info).ok()) return std::nullopt;
  return info;
}

std::optional<v1::JobInfo> WaitWhile(v1::Simplifier::Stub& stub, const std::string& id,
                                     v1::JobState state, double timeout_seconds) {
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (std::chrono::steady_clock::now() < end) {
    std::optional<v1::JobInfo> info = GetJob(stub, id);
    if (!info || info->state() != state) return info;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return std::nullopt;
}

grpc::Status SendRaw(v1::Simplifier::Stub& stub, const std::vector<v1::SimplifyRequest>& requests) {
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  auto stream = stub.Simplify(&ctx);
  for (const auto& r : requests)
    if (!stream->Write(r)) break;
  stream->WritesDone();
  v1::SimplifyResponse resp;
  while (stream->Read(&resp)) {
  }
  return stream->Finish();
}

int ConnectLoopback(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

std::string HttpExchange(int port, const std::string& request) {
  const int fd = ConnectLoopback(port);
  if (fd < 0) return "";
  if (write(fd, request.data(), request.size()) != static_cast<ssize_t>(request.size())) {
    close(fd);
    return "";
  }
  std::string resp;
  char buf[65536];
  for (ssize_t n; (n = read(fd, buf, sizeof buf)) > 0;) resp.append(buf, static_cast<size_t>(n));
  close(fd);
  return resp;
}

std::string HttpGet(int port, const std::string& path) {
  const std::string resp =
      HttpExchange(port, absl::StrCat("GET ", path, " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n"));
  size_t body = resp.find("\r\n\r\n");
  return body == std::string::npos ? "" : resp.substr(body + 4);
}

std::map<std::string, double> ParseMetrics(const std::string& text) {
  std::map<std::string, double> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    size_t sp = line.rfind(' ');
    if (sp == std::string::npos) continue;
    out[line.substr(0, sp)] = std::strtod(line.c_str() + sp + 1, nullptr);
  }
  return out;
}

int FreePort() {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  int port = ntohs(addr.sin_port);
  close(fd);
  return port;
}

server::ServerConfig OneWorkerConfig() {
  server::ServerConfig c = TestConfig();
  c.workers = 1;
  c.threads_per_job = 1;
  return c;
}

void ExpectWorkerFree(InProcessServer& s) {
  grpc::ClientContext ictx;
  v1::ServerInfoResponse info;
  ASSERT_TRUE(s.stub().ServerInfo(&ictx, {}, &info).ok());
  EXPECT_EQ(info.running_jobs(), 0u);
  EXPECT_EQ(info.queued_jobs(), 0u);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  cli::RemoteOutcome next =
      cli::RemoteSimplify(s.stub(), ctx, RatioSpec(0.5), LoadTestMesh("fandisk.off"));
  EXPECT_TRUE(next.status.ok()) << next.status.error_message();
}

}  // namespace femsimp::testing
