#include "tests/service/test_util.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <thread>

#include "absl/strings/str_cat.h"
#include "engine/io/mesh_io.h"
#include "gtest/gtest.h"

namespace femsimp::testing {

RawMesh MakeTorus(int n, int m) {
  RawMesh mesh;
  const double R = 3.0, r = 1.0, kPi = 3.14159265358979323846;
  mesh.positions.reserve(3 * size_t(n) * m);
  for (int i = 0; i < n; ++i) {
    double u = 2 * kPi * i / n;
    for (int j = 0; j < m; ++j) {
      double v = 2 * kPi * j / m;
      mesh.positions.push_back(float((R + r * std::cos(v)) * std::cos(u)));
      mesh.positions.push_back(float((R + r * std::cos(v)) * std::sin(u)));
      mesh.positions.push_back(float(r * std::sin(v)));
    }
  }
  mesh.triangles.reserve(6 * size_t(n) * m);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      uint32_t a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
               d = i * m + (j + 1) % m;
      mesh.triangles.insert(mesh.triangles.end(), {a, b, c, a, c, d});
    }
  return mesh;
}

RawMesh LoadTestMesh(const std::string& name) {
  absl::StatusOr<RawMesh> m = ReadMeshFile(absl::StrCat(FEMSIMP_TEST_DATA, "/", name));
  EXPECT_TRUE(m.ok()) << m.status();
  return m.ok() ? std::move(*m) : RawMesh();
}

RawMesh WithGroupsAndFields(RawMesh mesh) {
  const size_t nf = mesh.num_faces();
  mesh.face_groups.resize(nf);
  mesh.face_fields = {{"pressure", {}}, {"heat_flux", {}}};
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t g = 10 + uint32_t(4 * f / nf);
    mesh.face_groups[f] = g;
    mesh.face_fields[0].values.push_back(1000.0f + float(g));
    mesh.face_fields[1].values.push_back(-0.5f * float(g));
  }
  return mesh;
}

size_t ExpectGroupsAndFields(const RawMesh& out) {
  EXPECT_EQ(out.face_groups.size(), out.num_faces());
  EXPECT_EQ(out.face_fields.size(), 2u);
  if (out.face_groups.size() != out.num_faces() || out.face_fields.size() != 2) return 0;
  EXPECT_EQ(out.face_fields[0].name, "pressure");
  EXPECT_EQ(out.face_fields[1].name, "heat_flux");
  std::set<uint32_t> seen;
  for (size_t f = 0; f < out.num_faces(); ++f) {
    const uint32_t g = out.face_groups[f];
    EXPECT_TRUE(g >= 10 && g <= 13) << "face " << f << " group " << g;
    if (!(g >= 10 && g <= 13)) return 0;
    seen.insert(g);
    EXPECT_EQ(out.face_fields[0].values[f], 1000.0f + float(g)) << "face " << f;
    EXPECT_EQ(out.face_fields[1].values[f], -0.5f * float(g)) << "face " << f;
  }
  return seen.size();
}

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

std::string HttpGet(int port, const std::string& path) {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return "";
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return "";
  }
  std::string req = absl::StrCat("GET ", path, " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n");
  if (write(fd, req.data(), req.size()) != static_cast<ssize_t>(req.size())) {
    close(fd);
    return "";
  }
  std::string resp;
  char buf[65536];
  for (ssize_t n; (n = read(fd, buf, sizeof buf)) > 0;) resp.append(buf, static_cast<size_t>(n));
  close(fd);
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

}  // namespace femsimp::testing
