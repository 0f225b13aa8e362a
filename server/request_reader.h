// Reads and checks the request side of a Simplify call: the job spec first, then mesh chunks
// up to the declared counts. Every problem comes back as a status naming it (INVALID_ARGUMENT,
// or RESOURCE_EXHAUSTED for a server limit).
#pragma once

#include <functional>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"
#include "femsimp/v1/femsimp.pb.h"
#include "server/config.h"

namespace femsimp::server {

class RequestReader {
 public:
  // read() returns false at the end of the stream (half-close, cancel or broken connection).
  using ReadFn = std::function<bool(v1::SimplifyRequest*)>;
  RequestReader(ReadFn read, const ServerConfig& config)
      : read_(std::move(read)), config_(config) {}

  // The first message, which must be a spec with sizes inside the server's limits.
  absl::StatusOr<v1::JobSpec> ReadSpec();
  // The chunks after the spec, to the end of the stream.
  absl::StatusOr<RawMesh> ReadMesh(const v1::JobSpec& spec);

 private:
  ReadFn read_;
  const ServerConfig& config_;
};

// Spec checks alone (sizes, limits, label, face field names); used by ReadSpec.
absl::Status CheckSpec(const v1::JobSpec& spec, const ServerConfig& config);

}  // namespace femsimp::server
