// One Simplify call from the client side: stream the spec and the mesh, collect the responses.
// Shared by `femsimp simplify --server`, femsimp-load and the service tests.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "client/channel_security.h"
#include "engine/raw_mesh.h"
#include "femsimp/v1/femsimp.grpc.pb.h"
#include "grpcpp/channel.h"
#include "grpcpp/client_context.h"

namespace femsimp::cli {

struct RemoteCallbacks {
  std::function<void(const v1::Accepted&)> on_accepted;
  std::function<void(const v1::QueueUpdate&)> on_queue_update;
  std::function<void(const v1::Progress&)> on_progress;
  std::function<void(const v1::RepairReport&)> on_repair;  // the upload repaired, not queued yet
};

struct RemoteOutcome {
  grpc::Status status;
  v1::Result result;
  std::string job_id;
  RawMesh output;  // when keep_output
  // grpc-retry-pushback-ms from the trailers when the server sent one; -1 when it was negative
  // or unparseable (the server asks not to retry).
  std::optional<int> retry_pushback_ms;
  int progress_messages = 0;
  int chunks_received = 0;
};

// Sets vertex/face counts in the spec from the mesh, sends it and the chunks, reads to the end.
// The status is the call's, or INTERNAL/DATA_LOSS when the response stream was malformed or
// incomplete (without keep_output the chunks are not assembled, but their vertex and face counts
// must still add up to the Result's).
RemoteOutcome RemoteSimplify(v1::Simplifier::Stub& stub, grpc::ClientContext& ctx, v1::JobSpec spec,
                             const RawMesh& mesh, const RemoteCallbacks& callbacks = {},
                             bool keep_output = true);

// Channel arguments suitable for mesh streams (result chunks are below 4 MiB, but allow more).
// A distinct channel_index gives a channel of its own (gRPC shares connections between channels
// with equal arguments).
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target, int channel_index = 0);
// The same with TLS and a bearer token on every call (client/channel_security.h).
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target,
                                           const ChannelSecurity& security, int channel_index = 0);

}  // namespace femsimp::cli

namespace femsimp::cli {

// "CANCELLED", "RESOURCE_EXHAUSTED", ...
const char* GrpcCodeName(grpc::StatusCode code);
// What the code means for a femsimp user, one short sentence.
const char* GrpcCodeHint(grpc::StatusCode code);

}  // namespace femsimp::cli
