#include "client/remote_call.h"

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "grpcpp/create_channel.h"
#include "grpcpp/security/credentials.h"
#include "proto/wire.h"

namespace femsimp::cli {

std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target, int channel_index) {
  grpc::ChannelArguments args;
  if (channel_index) args.SetInt("femsimp.channel_index", channel_index);
  args.SetMaxReceiveMessageSize(64 << 20);
  return grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args);
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
  v1::SimplifyResponse resp;
  while (stream->Read(&resp)) {
    switch (resp.payload_case()) {
      case v1::SimplifyResponse::kAccepted:
        out.job_id = resp.accepted().job_id();
        if (callbacks.on_accepted) callbacks.on_accepted(resp.accepted());
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
          assembler.emplace(out.result.output_vertices(), out.result.output_faces(),
                            out.result.has_face_groups(),
                            std::vector<std::string>(out.result.face_field_names().begin(),
                                                     out.result.face_field_names().end()));
        }
        break;
      case v1::SimplifyResponse::kChunk:
        ++out.chunks_received;
        if (assembler && malformed.ok()) malformed = assembler->Add(resp.chunk());
        break;
      default:
        break;
    }
  }
  out.status = stream->Finish();
  const auto& trailers = ctx.GetServerTrailingMetadata();
  if (auto it = trailers.find("grpc-retry-pushback-ms"); it != trailers.end()) {
    int ms;
    if (absl::SimpleAtoi(std::string(it->second.data(), it->second.size()), &ms))
      out.retry_pushback_ms = ms;
  }
  if (!out.status.ok()) return out;
  if (out.result.job_id().empty()) {
    out.status = grpc::Status(grpc::StatusCode::INTERNAL, "server ended the call without a result");
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
