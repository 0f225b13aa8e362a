// The /metrics responder (server/metrics_http.h): answers, refusals, and that idle connections,
// however many, cannot hold a scrape.
#include "server/metrics_http.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "prometheus/counter.h"
#include "tests/service/test_util.h"

namespace femsimp::server {
namespace {

struct Served {
  Served() : registry(std::make_shared<prometheus::Registry>()) {
    prometheus::BuildCounter()
        .Name("probe_total")
        .Help("a counter")
        .Register(*registry)
        .Add({})
        .Increment(3);
    absl::StatusOr<std::unique_ptr<MetricsHttpServer>> s =
        MetricsHttpServer::Start("127.0.0.1:0", registry);
    EXPECT_TRUE(s.ok()) << s.status();
    if (s.ok()) server = std::move(*s);
  }
  int port() const { return server->port(); }
  std::shared_ptr<prometheus::Registry> registry;
  std::unique_ptr<MetricsHttpServer> server;
};

TEST(MetricsHttp, AnswersTheRegistryAndRefusesTheRest) {
  Served s;
  ASSERT_NE(s.server, nullptr);
  const std::string ok =
      testing::HttpExchange(s.port(), "GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(ok.rfind("HTTP/1.1 200 OK\r\n", 0), 0u) << ok;
  EXPECT_NE(ok.find("Content-Type: text/plain; version=0.0.4"), std::string::npos);
  EXPECT_EQ(testing::ParseMetrics(ok.substr(ok.find("\r\n\r\n") + 4))["probe_total"], 3);
  EXPECT_NE(testing::HttpGet(s.port(), "/metrics?x=1").find("probe_total 3"), std::string::npos);
  EXPECT_EQ(testing::HttpExchange(s.port(), "GET / HTTP/1.0\r\n\r\n").rfind("HTTP/1.1 404", 0), 0u);
  EXPECT_EQ(
      testing::HttpExchange(s.port(), "POST /metrics HTTP/1.0\r\n\r\n").rfind("HTTP/1.1 405", 0),
      0u);
  EXPECT_EQ(testing::HttpExchange(s.port(), "GET /metrics HTTP/1.0\r\n" + std::string(9000, 'x'))
                .rfind("HTTP/1.1 431", 0),
            0u);
}

// More idle connections than the responder keeps (the oldest are dropped), and half-sent
// requests: a scrape beside them is answered at once, and they are closed after their time.
TEST(MetricsHttp, IdleConnectionsCannotHoldAScrape) {
  Served s;
  ASSERT_NE(s.server, nullptr);
  std::vector<int> idle;
  for (size_t i = 0; i < MetricsHttpServer::kMaxConnections + 44; ++i) {
    const int fd = testing::ConnectLoopback(s.port());
    ASSERT_GE(fd, 0);
    if (i % 2 == 1) {
      ASSERT_EQ(write(fd, "GET /met", 8), 8);
    }
    idle.push_back(fd);
  }
  for (int i = 0; i < 5; ++i) {
    const auto start = std::chrono::steady_clock::now();
    EXPECT_NE(testing::HttpGet(s.port(), "/metrics").find("probe_total 3"), std::string::npos);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(1000));
  }
  // Every idle connection is closed by the server within its request time (and then some).
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::milliseconds(MetricsHttpServer::kRequestTimeoutMs + 5000);
  size_t closed = 0;
  for (int fd : idle) {
    timeval tv{};
    tv.tv_sec = 1;
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    char c;
    while (std::chrono::steady_clock::now() < until) {
      const ssize_t n = read(fd, &c, 1);
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
        ++closed;
        break;
      }
    }
    close(fd);
  }
  EXPECT_EQ(closed, idle.size());
}

TEST(MetricsHttp, APortInUseIsAnError) {
  Served s;
  ASSERT_NE(s.server, nullptr);
  absl::StatusOr<std::unique_ptr<MetricsHttpServer>> again =
      MetricsHttpServer::Start(absl::StrCat("127.0.0.1:", s.port()), s.registry);
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.status().message().find("cannot listen on 127.0.0.1:"), std::string::npos)
      << again.status();
  EXPECT_FALSE(MetricsHttpServer::Start("no-port", s.registry).ok());
}

}  // namespace
}  // namespace femsimp::server
