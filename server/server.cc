#include "server/server.h"

#include <dlfcn.h>

#include <chrono>
#include <thread>

#include "absl/strings/str_cat.h"
#include "grpcpp/health_check_service_interface.h"
#include "grpcpp/security/server_credentials.h"
#include "grpcpp/server_builder.h"
#include "server/decode_errors.h"
#include "server/log.h"
#include "server/transport_security.h"

namespace femsimp::server {
namespace {

constexpr char kServiceName[] = "femsimp.v1.Simplifier";

// gRPC's reflection library registers its server plugin when it is loaded, for every server the
// process builds after: loaded only when asked for (and then for good).
absl::Status LoadReflection() {
  if (dlopen(FEMSIMP_GRPC_REFLECTION_LIBRARY, RTLD_NOW | RTLD_GLOBAL) != nullptr)
    return absl::OkStatus();
  const char* why = dlerror();
  return absl::FailedPreconditionError(absl::StrCat("--reflection: cannot load ",
                                                    FEMSIMP_GRPC_REFLECTION_LIBRARY, ": ",
                                                    why != nullptr ? why : "unknown error"));
}

}  // namespace

FemsimpServer::FemsimpServer(ServerConfig config)
    : config_(std::move(config)),
      queue_(static_cast<size_t>(std::max(0, config_.queue_capacity))),
      registry_(config_.finished_jobs_kept) {}

FemsimpServer::~FemsimpServer() { Shutdown(); }

absl::Status FemsimpServer::Start() {
  if (std::string err = NormalizeConfig(&config_); !err.empty())
    return absl::InvalidArgumentError(err);
  if (!config_.metrics_listen.empty())
    if (absl::Status s = metrics_.StartExposer(config_.metrics_listen); !s.ok()) return s;

  TokenAuthenticator auth;
  if (!config_.auth_tokens_file.empty()) {
    absl::StatusOr<TokenAuthenticator> loaded =
        TokenAuthenticator::FromFile(config_.auth_tokens_file);
    if (!loaded.ok()) return loaded.status();
    auth = *std::move(loaded);
  }
  runner_ = std::make_unique<JobRunner>(config_.workers, queue_, registry_, metrics_);
  service_ = std::make_unique<SimplifierService>(config_, queue_, registry_, *runner_, metrics_,
                                                 std::move(auth));
  grpc::EnableDefaultHealthCheckService(true);
  if (config_.reflection)
    if (absl::Status s = LoadReflection(); !s.ok()) return s;
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> credentials =
      ListeningCredentials(config_);
  if (!credentials.ok()) {
    runner_.reset();
    return credentials.status();
  }
  grpc::ServerBuilder builder;
  // A second server on a taken port must fail, not share it (gRPC sets SO_REUSEPORT otherwise).
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.AddListeningPort(config_.listen, *credentials, &port_);
  builder.SetMaxReceiveMessageSize(static_cast<int>(
      std::min<uint64_t>(config_.max_request_bytes, std::numeric_limits<int>::max())));
  builder.RegisterService(service_.get());
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(std::make_unique<UndecodableRequestInterceptorFactory>());
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  if (config_.max_connection_age_seconds > 0)
    builder.AddChannelArgument(
        GRPC_ARG_MAX_CONNECTION_AGE_MS,
        static_cast<int>(std::min(config_.max_connection_age_seconds * 1e3, 2e9)));
  server_ = builder.BuildAndStart();
  if (!server_ || port_ == 0) {
    runner_.reset();
    return absl::UnavailableError(absl::StrCat("cannot listen on ", config_.listen));
  }
  server_->GetHealthCheckService()->SetServingStatus(true);
  server_->GetHealthCheckService()->SetServingStatus(kServiceName, true);
  LogLine(absl::StrCat(
      "femsimp-server ", kVersion, " listening on ", config_.listen, " (port ", port_,
      "), metrics on ", config_.metrics_listen.empty() ? "(off)" : config_.metrics_listen,
      " (port ", metrics_.port(), "), workers=", config_.workers,
      " queue_capacity=", config_.queue_capacity, " threads_per_job=", config_.threads_per_job,
      " memory_budget=", config_.memory_budget_mib, "MiB", " reflection=",
      config_.reflection ? "on" : "off", " transport=", TransportDescription(config_), " tenants=",
      service_->tenants() > 0 ? absl::StrCat(service_->tenants(), " (bearer tokens)")
                              : std::string("off")));
  return absl::OkStatus();
}

void FemsimpServer::Shutdown() {
  if (stopped_ || !server_) return;
  stopped_ = true;
  LogLine("shutting down: health NOT_SERVING, no new jobs");
  server_->GetHealthCheckService()->SetServingStatus(false);
  server_->GetHealthCheckService()->SetServingStatus(kServiceName, false);
  service_->BeginShutdown();
  queue_.Close();
  for (const std::shared_ptr<Job>& job : queue_.TakeAll()) {
    const grpc::Status s(grpc::StatusCode::UNAVAILABLE, "server shut down before the job started");
    job->RequestCancel(s.error_code(), s.error_message());
    job->Finish(JobState::kCancelled, s);
  }
  metrics_.SetQueueDepth(0);

  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration<double>(config_.grace_period_seconds);
  while (runner_->running() > 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (runner_->running() > 0) {
    LogLine(absl::StrCat("grace period over: cancelling ", runner_->running(), " running jobs"));
    for (const std::shared_ptr<Job>& job : registry_.Unfinished())
      job->RequestCancel(grpc::StatusCode::UNAVAILABLE,
                         "server shut down: grace period over, job cancelled");
  }
  runner_->Join();
  // Handlers are only streaming results now; give them a moment, then cut the calls. Waited for
  // here rather than by Shutdown's deadline alone: gRPC holds that deadline for any idle client
  // connection too, so every SIGTERM took 5 s longer than its jobs (the hostile probe). The
  // short deadline left lets the last handlers' statuses reach the wire.
  const auto cut = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (service_->active_simplify_calls() > 0 && std::chrono::steady_clock::now() < cut)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::milliseconds(250));
  server_->Wait();
  LogLine("stopped");
}

}  // namespace femsimp::server
