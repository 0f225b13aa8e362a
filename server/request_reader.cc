#include "server/request_reader.h"

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "proto/wire.h"

namespace femsimp::server {

absl::Status CheckSpec(const v1::JobSpec& spec, const ServerConfig& config) {
  if (spec.vertex_count() < 3)
    return absl::InvalidArgumentError(
        absl::StrCat("spec: vertex_count = ", spec.vertex_count(), " (a mesh needs at least 3)"));
  if (spec.face_count() < 1)
    return absl::InvalidArgumentError("spec: face_count = 0 (a mesh needs at least 1 face)");
  if (spec.vertex_count() > config.max_vertices)
    return absl::ResourceExhaustedError(
        absl::StrCat("spec: vertex_count = ", spec.vertex_count(),
                     " exceeds the server limit max_vertices = ", config.max_vertices));
  if (spec.face_count() > config.max_faces)
    return absl::ResourceExhaustedError(
        absl::StrCat("spec: face_count = ", spec.face_count(),
                     " exceeds the server limit max_faces = ", config.max_faces));
  if (spec.client_label().size() > 128)
    return absl::InvalidArgumentError(
        absl::StrCat("spec: client_label is ", spec.client_label().size(), " bytes (at most 128)"));
  if (absl::Status s = wire::OriginFromProto(spec.origin(), "spec: origin").status(); !s.ok())
    return s;
  return wire::CheckFieldNames(spec.face_field_names(), "spec: face_field_names");
}

absl::StatusOr<v1::JobSpec> RequestReader::ReadSpec() {
  v1::SimplifyRequest req;
  if (!read_(&req))
    // gRPC ends a stream whose next message cannot be decoded as it ends a half-closed one.
    return absl::InvalidArgumentError(
        "stream ended before the job spec: the client half-closed without sending one, or its "
        "first message could not be decoded as a femsimp.v1.SimplifyRequest (send a spec "
        "first)");
  if (req.payload_case() != v1::SimplifyRequest::kSpec)
    return absl::InvalidArgumentError(
        req.payload_case() == v1::SimplifyRequest::kChunk
            ? "first message is a mesh chunk: the job spec must come first"
            : "first message is empty: the job spec must come first");
  if (absl::Status s = CheckSpec(req.spec(), config_); !s.ok()) return s;
  return std::move(*req.mutable_spec());
}

absl::StatusOr<RawMesh> RequestReader::ReadMesh(const v1::JobSpec& spec) {
  wire::MeshAssembler assembler(
      spec.vertex_count(), spec.face_count(), spec.has_face_groups(),
      std::vector<std::string>(spec.face_field_names().begin(), spec.face_field_names().end()),
      *wire::OriginFromProto(spec.origin(), "spec: origin"));  // checked by CheckSpec
  v1::SimplifyRequest req;
  while (read_(&req)) {
    switch (req.payload_case()) {
      case v1::SimplifyRequest::kSpec:
        return absl::InvalidArgumentError(absl::StrCat(
            "a second job spec after ", assembler.chunks(), " chunks (one spec per call)"));
      case v1::SimplifyRequest::kChunk:
        if (absl::Status s = assembler.Add(req.chunk()); !s.ok()) return s;
        break;
      default:
        return absl::InvalidArgumentError(
            absl::StrCat("message ", assembler.chunks() + 2, " is empty (neither spec nor chunk)"));
    }
  }
  absl::StatusOr<RawMesh> mesh = assembler.Finish();
  if (!mesh.ok())  // the stream ended early, for either reason ReadSpec names
    return absl::InvalidArgumentError(
        absl::StrCat(mesh.status().message(),
                     " (the client half-closed, or a message could not be decoded as a "
                     "femsimp.v1.SimplifyRequest)"));
  return mesh;
}

}  // namespace femsimp::server
