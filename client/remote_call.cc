#include "client/remote_call.h"

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "client/channel_security.h"
#include "grpcpp/create_channel.h"
#include "grpcpp/security/credentials.h"
#include "grpcpp/support/client_interceptor.h"
#include "proto/wire.h"

namespace femsimp::cli {

namespace {

// Adds the bearer token to every call's initial metadata (a plaintext channel cannot carry call
// credentials, and the token must reach a server behind a TLS-terminating proxy too).
class BearerToken final : public grpc::experimental::Interceptor {
 public:
  explicit BearerToken(const std::string& value) : value_(value) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA))
      methods->GetSendInitialMetadata()->insert({"authorization", value_});
    methods->Proceed();
  }

 private:
  const std::string& value_;
};

class BearerTokenFactory final : public grpc::experimental::ClientInterceptorFactoryInterface {
 public:
  explicit BearerTokenFactory(std::string token) : value_("Bearer " + std::move(token)) {}
  grpc::experimental::Interceptor* CreateClientInterceptor(
      grpc::experimental::ClientRpcInfo*) override {
    return new BearerToken(value_);
  }

 private:
  const std::string value_;  // outlives the channel's calls: the channel owns the factory
};

}  // namespace

std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target, int channel_index) {
  return MakeChannel(target, ChannelSecurity{}, channel_index);
}

std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target,
                                           const ChannelSecurity& security, int channel_index) {
  grpc::ChannelArguments args;
  if (channel_index) args.SetInt("femsimp.channel_index", channel_index);
  args.SetMaxReceiveMessageSize(64 << 20);
  // Reconnect about as soon as a retry (retry.h) would come back, not after gRPC's default 1 s
  // growing to 120 s: a restarted replica is used again within seconds.
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 250);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 8000);
  // A target that resolves to several replicas (a headless Service via dns:///, or
  // ipv4:a:p,b:p) gets calls spread over all of them; a single address works as before.
  args.SetLoadBalancingPolicyName("round_robin");
  const std::shared_ptr<grpc::ChannelCredentials> credentials =
      security.credentials ? security.credentials : grpc::InsecureChannelCredentials();
  if (security.token.empty()) return grpc::CreateCustomChannel(target, credentials, args);
  std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> factories;
  factories.push_back(std::make_unique<BearerTokenFactory>(security.token));
  return grpc::experimental::CreateCustomChannelWithInterceptors(target, credentials, args,
                                                                 std::move(factories));
}

RemoteOutcome RemoteSimplify(v1::Simplifier::Stub& stub, grpc::ClientContext& ctx, v1::JobSpec spec,
                             const RawMesh& mesh, const RemoteCallbacks& callbacks,
                             bool keep_output) {
  RemoteOutcome out;
  spec.set_vertex_count(mesh.num_vertices());
  spec.set_face_count(mesh.num_faces());
  spec.set_has_face_groups(!mesh.face_groups.empty());
  spec.clear_face_field_names();
  for (const FaceField& field : mesh.face_fields) spec.add_face_field_names(field.name);
  wire::OriginToProto(mesh.origin, spec.mutable_origin());
  std::unique_ptr<grpc::ClientReaderWriter<v1::SimplifyRequest, v1::SimplifyResponse>> stream =
      stub.Simplify(&ctx);

  // Upload. A failed write means the server already ended the call; Finish() says why.
  v1::SimplifyRequest req;
  *req.mutable_spec() = std::move(spec);
  if (stream->Write(req)) {
    wire::ForEachChunk(mesh, [&](v1::MeshChunk& chunk) {
      v1::SimplifyRequest r;
      r.mutable_chunk()->Swap(&chunk);
      return stream->Write(r);
    });
  }
  stream->WritesDone();

  std::optional<wire::MeshAssembler> assembler;
  absl::Status malformed;
  uint64_t vertices_received = 0, faces_received = 0;
  v1::SimplifyResponse resp;
  while (stream->Read(&resp)) {
    switch (resp.payload_case()) {
      case v1::SimplifyResponse::kAccepted:
        out.job_id = resp.accepted().job_id();
        if (callbacks.on_accepted) callbacks.on_accepted(resp.accepted());
        break;
      case v1::SimplifyResponse::kRepair:
        if (callbacks.on_repair) callbacks.on_repair(resp.repair());
        break;
      case v1::SimplifyResponse::kQueueUpdate:
        if (callbacks.on_queue_update) callbacks.on_queue_update(resp.queue_update());
        break;
      case v1::SimplifyResponse::kProgress:
        ++out.progress_messages;
        if (callbacks.on_progress) callbacks.on_progress(resp.progress());
        break;
      case v1::SimplifyResponse::kResult:
        out.result = resp.result();
        if (keep_output) {
          malformed =
              wire::CheckFieldNames(out.result.face_field_names(), "result: face_field_names");
          absl::StatusOr<std::array<double, 3>> origin =
              wire::OriginFromProto(out.result.origin(), "result: origin");
          if (malformed.ok()) malformed = origin.status();
          assembler.emplace(out.result.output_vertices(), out.result.output_faces(),
                            out.result.has_face_groups(),
                            std::vector<std::string>(out.result.face_field_names().begin(),
                                                     out.result.face_field_names().end()),
                            origin.ok() ? *origin : std::array<double, 3>{});
        }
        break;
      case v1::SimplifyResponse::kChunk:
        ++out.chunks_received;
        vertices_received += static_cast<uint64_t>(resp.chunk().positions_size()) / 3;
        faces_received += static_cast<uint64_t>(resp.chunk().indices_size()) / 3;
        if (assembler && malformed.ok()) malformed = assembler->Add(resp.chunk());
        break;
      default:
        break;
    }
  }
  out.status = stream->Finish();
  // A stream reset before the server's status means the call was cut, not answered: nginx
  // resets the client's stream with NO_ERROR when the replica behind it dies, which gRPC reports
  // as INTERNAL. For the client that is a server gone away, UNAVAILABLE (and retryable).
  if (out.status.error_code() == grpc::StatusCode::INTERNAL &&
      absl::StartsWith(out.status.error_message(), "Received RST_STREAM"))
    out.status = grpc::Status(
        grpc::StatusCode::UNAVAILABLE,
        absl::StrCat("the call was cut before the server answered (", out.status.error_message(),
                     "); a replica behind a proxy went away?"));
  const auto& trailers = ctx.GetServerTrailingMetadata();
  if (auto it = trailers.find("grpc-retry-pushback-ms"); it != trailers.end()) {
    int ms;
    out.retry_pushback_ms =
        absl::SimpleAtoi(std::string(it->second.data(), it->second.size()), &ms) && ms >= 0 ? ms
                                                                                            : -1;
  }
  if (!out.status.ok()) return out;
  if (out.result.job_id().empty()) {
    out.status = grpc::Status(grpc::StatusCode::INTERNAL, "server ended the call without a result");
    return out;
  }
  // Done means the whole result arrived: without assembly, at least the counts must add up.
  if (!keep_output && (vertices_received != out.result.output_vertices() ||
                       faces_received != out.result.output_faces())) {
    out.status =
        grpc::Status(grpc::StatusCode::DATA_LOSS,
                     absl::StrCat("result mesh incomplete: received ", vertices_received, " of ",
                                  out.result.output_vertices(), " vertices and ", faces_received,
                                  " of ", out.result.output_faces(), " faces"));
    return out;
  }
  if (keep_output) {
    if (malformed.ok()) {
      absl::StatusOr<RawMesh> raw = assembler->Finish();
      if (raw.ok()) {
        out.output = std::move(*raw);
      } else {
        malformed = raw.status();
      }
    }
    if (!malformed.ok())
      out.status = grpc::Status(grpc::StatusCode::DATA_LOSS,
                                absl::StrCat("malformed result mesh: ", malformed.message()));
  }
  return out;
}

}  // namespace femsimp::cli

namespace femsimp::cli {

const char* GrpcCodeName(grpc::StatusCode code) {
  static const char* const kNames[] = {"OK",
                                       "CANCELLED",
                                       "UNKNOWN",
                                       "INVALID_ARGUMENT",
                                       "DEADLINE_EXCEEDED",
                                       "NOT_FOUND",
                                       "ALREADY_EXISTS",
                                       "PERMISSION_DENIED",
                                       "RESOURCE_EXHAUSTED",
                                       "FAILED_PRECONDITION",
                                       "ABORTED",
                                       "OUT_OF_RANGE",
                                       "UNIMPLEMENTED",
                                       "INTERNAL",
                                       "UNAVAILABLE",
                                       "DATA_LOSS",
                                       "UNAUTHENTICATED"};
  int i = static_cast<int>(code);
  return i >= 0 && i <= 16 ? kNames[i] : "UNKNOWN";
}

const char* GrpcCodeHint(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK:
      return "success";
    case grpc::StatusCode::CANCELLED:
      return "the job was cancelled (by you, CancelJob or the server)";
    case grpc::StatusCode::INVALID_ARGUMENT:
      return "the server rejected the request or the mesh";
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return "the job did not finish within --deadline";
    case grpc::StatusCode::NOT_FOUND:
      return "no such job or method on the server";
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return "the server is full or the mesh exceeds one of its limits";
    case grpc::StatusCode::UNIMPLEMENTED:
      return "the server does not support this (back end or feature not available, or a version "
             "mismatch)";
    case grpc::StatusCode::INTERNAL:
      return "the server failed internally";
    case grpc::StatusCode::UNAVAILABLE:
      return "the server is not reachable or is shutting down; retry later";
    case grpc::StatusCode::DATA_LOSS:
      return "the result mesh arrived incomplete or malformed";
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::PERMISSION_DENIED:
      return "the server refused the client's credentials";
    default:
      return "the call failed";
  }
}

}  // namespace femsimp::cli
