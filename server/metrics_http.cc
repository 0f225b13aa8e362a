#include "server/metrics_http.h"

#include <netdb.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <unordered_map>

#include "absl/strings/str_cat.h"
#include "prometheus/text_serializer.h"

namespace femsimp::server {
namespace {

using Clock = std::chrono::steady_clock;

absl::Status ListenError(const std::string& address, const std::string& why) {
  return absl::UnavailableError(absl::StrCat("metrics: cannot listen on ", address, ": ", why));
}

std::string Response(const std::string& status, const std::string& content_type,
                     const std::string& body) {
  return absl::StrCat("HTTP/1.1 ", status, "\r\nContent-Type: ", content_type,
                      "\r\nContent-Length: ", body.size(), "\r\nConnection: close\r\n\r\n", body);
}

// Where a request head ends (after its blank line), or npos while it is incomplete.
size_t HeadEnd(const std::string& in) {
  const size_t crlf = in.find("\r\n\r\n");
  if (crlf != std::string::npos) return crlf + 4;
  const size_t lf = in.find("\n\n");
  return lf == std::string::npos ? std::string::npos : lf + 2;
}

}  // namespace

absl::StatusOr<std::unique_ptr<MetricsHttpServer>> MetricsHttpServer::Start(
    const std::string& address, std::shared_ptr<prometheus::Registry> registry) {
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos) return ListenError(address, "not HOST:PORT");
  std::string host = address.substr(0, colon);
  const std::string port = address.substr(colon + 1);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (const int e =
          getaddrinfo(host.empty() ? nullptr : host.c_str(), port.c_str(), &hints, &found);
      e != 0)
    return ListenError(address, gai_strerror(e));
  int fd = -1;
  std::string why = "no address";
  for (addrinfo* a = found; a != nullptr && fd < 0; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      why = std::strerror(errno);
      continue;
    }
    const int on = 1;  // a restarted server takes its port back from TIME_WAIT (not shared)
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (bind(fd, a->ai_addr, a->ai_addrlen) != 0 || listen(fd, 128) != 0) {
      why = std::strerror(errno);
      close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(found);
  if (fd < 0) return ListenError(address, why);
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  const int bound_port = bound.ss_family == AF_INET6
                             ? ntohs(reinterpret_cast<const sockaddr_in6*>(&bound)->sin6_port)
                             : ntohs(reinterpret_cast<const sockaddr_in*>(&bound)->sin_port);
  const int wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake < 0) {
    close(fd);
    return ListenError(address, std::strerror(errno));
  }
  std::unique_ptr<MetricsHttpServer> server(
      new MetricsHttpServer(fd, wake, bound_port, std::move(registry)));
  server->thread_ = std::thread([s = server.get()] { s->Serve(); });
  return server;
}

MetricsHttpServer::MetricsHttpServer(int listen_fd, int wake_fd, int port,
                                     std::shared_ptr<prometheus::Registry> registry)
    : listen_fd_(listen_fd), wake_fd_(wake_fd), port_(port), registry_(std::move(registry)) {}

MetricsHttpServer::~MetricsHttpServer() {
  stop_.store(true);
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = write(wake_fd_, &one, sizeof one);
  if (thread_.joinable()) thread_.join();
  close(listen_fd_);
  close(wake_fd_);
}

std::string MetricsHttpServer::Answer(const std::string& head) const {
  const size_t line_end = head.find_first_of("\r\n");
  const std::string line = head.substr(0, line_end);
  const size_t sp1 = line.find(' ');
  const size_t sp2 = sp1 == std::string::npos ? std::string::npos : line.find(' ', sp1 + 1);
  if (sp1 == std::string::npos)
    return Response("400 Bad Request", "text/plain", "not an HTTP request\n");
  const std::string method = line.substr(0, sp1);
  std::string path = line.substr(sp1 + 1, sp2 == std::string::npos ? sp2 : sp2 - sp1 - 1);
  path = path.substr(0, path.find('?'));
  if (method != "GET") return Response("405 Method Not Allowed", "text/plain", "GET only\n");
  if (path != "/metrics") return Response("404 Not Found", "text/plain", "see /metrics\n");
  return Response("200 OK", "text/plain; version=0.0.4; charset=utf-8",
                  prometheus::TextSerializer().Serialize(registry_->Collect()));
}

void MetricsHttpServer::Serve() {
  const int ep = epoll_create1(EPOLL_CLOEXEC);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = listen_fd_;
  epoll_ctl(ep, EPOLL_CTL_ADD, listen_fd_, &ev);
  ev.data.fd = wake_fd_;
  epoll_ctl(ep, EPOLL_CTL_ADD, wake_fd_, &ev);

  struct Connection {
    std::string in, out;
    size_t sent = 0;
    Clock::time_point deadline;
    uint64_t serial = 0;
  };
  std::unordered_map<int, Connection> open;
  std::map<uint64_t, int> by_age;  // serial -> fd, oldest first
  uint64_t next_serial = 0;
  const auto drop = [&](int fd) {
    auto it = open.find(fd);
    if (it == open.end()) return;
    by_age.erase(it->second.serial);
    open.erase(it);
    epoll_ctl(ep, EPOLL_CTL_DEL, fd, nullptr);
    close(fd);
  };
  // Writes what it can; the connection ends once the answer is out (or the peer is gone).
  const auto flush = [&](int fd, Connection& c) {
    while (c.sent < c.out.size()) {
      const ssize_t n = send(fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL);
      if (n > 0) {
        c.sent += static_cast<size_t>(n);
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        return;
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else {
        break;
      }
    }
    drop(fd);
  };

  epoll_event events[64];
  while (!stop_.load()) {
    const int n = epoll_wait(ep, events, 64, 100);
    for (int i = 0; i < n && !stop_.load(); ++i) {
      const int fd = events[i].data.fd;
      if (fd == wake_fd_) continue;
      if (fd == listen_fd_) {
        for (;;) {
          const int c = accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
          if (c < 0) break;  // EAGAIN: all taken; anything else: the next wake-up retries
          if (open.size() >= kMaxConnections) drop(by_age.begin()->second);
          const uint64_t serial = next_serial++;
          Connection& added = open[c];
          added.deadline = Clock::now() + std::chrono::milliseconds(kRequestTimeoutMs);
          added.serial = serial;
          by_age[serial] = c;
          epoll_event cev{};
          cev.events = EPOLLIN | EPOLLRDHUP;
          cev.data.fd = c;
          epoll_ctl(ep, EPOLL_CTL_ADD, c, &cev);
        }
        continue;
      }
      auto it = open.find(fd);
      if (it == open.end()) continue;
      Connection& c = it->second;
      if (!c.out.empty()) {  // answering
        flush(fd, c);
        continue;
      }
      char buffer[4096];
      bool closed = false;
      for (;;) {
        const ssize_t got = recv(fd, buffer, sizeof buffer, 0);
        if (got > 0) {
          c.in.append(buffer, static_cast<size_t>(got));
          if (c.in.size() > kMaxRequestBytes) break;
        } else if (got < 0 && errno == EINTR) {
          continue;
        } else {
          closed = got == 0 || (errno != EAGAIN && errno != EWOULDBLOCK);
          break;
        }
      }
      const size_t end = HeadEnd(c.in);
      if (end != std::string::npos) {
        c.out = Answer(c.in.substr(0, end));
      } else if (c.in.size() > kMaxRequestBytes) {
        c.out = Response("431 Request Header Fields Too Large", "text/plain",
                         "request head over 8192 bytes\n");
      } else if (closed) {
        drop(fd);
        continue;
      } else {
        continue;
      }
      epoll_event wev{};
      wev.events = EPOLLOUT | EPOLLRDHUP;
      wev.data.fd = fd;
      epoll_ctl(ep, EPOLL_CTL_MOD, fd, &wev);
      flush(fd, c);
    }
    // Connections past their time (no request head yet, or an answer nobody reads) go; every
    // one gets the same time from its accept, so the oldest are the first due.
    const Clock::time_point now = Clock::now();
    while (!by_age.empty() && open.at(by_age.begin()->second).deadline <= now)
      drop(by_age.begin()->second);
  }
  while (!by_age.empty()) drop(by_age.begin()->second);
  close(ep);
}

}  // namespace femsimp::server
