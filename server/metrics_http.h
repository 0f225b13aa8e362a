// The /metrics endpoint: a small HTTP/1.x responder on one thread with an epoll loop, so that
// no number of idle or slow connections can hold a scrape. A thread-per-connection server
// (civetweb, prometheus-cpp's Exposer) gives each connection a thread until its request comes:
// with 8 threads, 24 idle connections delayed every scrape by 6 s (the hostile probe).
//
// Each connection has kRequestTimeout to send its request head (at most kMaxRequestBytes) and
// to take the answer, then is closed; one request per connection. At kMaxConnections the
// oldest connection is dropped to make room for the new one, so a scraper always gets in.
// GET /metrics answers the text exposition format of the registry; other paths 404, other
// methods 405.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "prometheus/registry.h"

namespace femsimp::server {

class MetricsHttpServer {
 public:
  static constexpr int kRequestTimeoutMs = 2000;
  static constexpr size_t kMaxRequestBytes = 8192;
  static constexpr size_t kMaxConnections = 256;

  // Listens on HOST:PORT ("[::1]:0"; port 0 picks a free one) and serves from its own thread.
  static absl::StatusOr<std::unique_ptr<MetricsHttpServer>> Start(
      const std::string& address, std::shared_ptr<prometheus::Registry> registry);
  ~MetricsHttpServer();  // stops the thread, closes every connection
  MetricsHttpServer(const MetricsHttpServer&) = delete;
  MetricsHttpServer& operator=(const MetricsHttpServer&) = delete;

  int port() const { return port_; }

 private:
  MetricsHttpServer(int listen_fd, int wake_fd, int port,
                    std::shared_ptr<prometheus::Registry> registry);
  void Serve();
  std::string Answer(const std::string& head) const;

  const int listen_fd_, wake_fd_, port_;
  const std::shared_ptr<prometheus::Registry> registry_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace femsimp::server
