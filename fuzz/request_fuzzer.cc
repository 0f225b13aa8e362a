// libFuzzer target for the server's request decoder (server/request_reader.h), without a network:
// the input is a sequence of SimplifyRequest messages, each a varint length and that many bytes
// (the framing gRPC's own length prefix gives them). The decoder reads them as the Simplify
// handler does: the spec and its checks, the engine and FE check options, the mesh chunks up to
// the declared counts, then the repair stage and Mesh::Build. A message protobuf cannot decode
// ends the stream there, as gRPC ends a call whose message it cannot decode. Seeds are real
// meshes cut into chunks (make_request_seeds.cc).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "google/protobuf/io/coded_stream.h"
#include "proto/fe_check_wire.h"
#include "proto/wire.h"
#include "server/config.h"
#include "server/request_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace femsimp;
  // The server's limits, but for the mesh size: a spec may declare 20 M vertices, and the
  // decoder's arrays grow with the chunks that arrive, not with the declaration; smaller limits
  // keep each run small without leaving a check out.
  server::ServerConfig config;
  config.max_vertices = 100'000;
  config.max_faces = 200'000;
  google::protobuf::io::CodedInputStream in(data, static_cast<int>(size));
  server::RequestReader reader(
      [&in](v1::SimplifyRequest* r) {
        uint32_t length;
        if (!in.ReadVarint32(&length)) return false;
        std::string bytes;
        if (!in.ReadString(&bytes, static_cast<int>(length))) return false;
        return r->ParseFromString(bytes);
      },
      config);
  absl::StatusOr<v1::JobSpec> spec = reader.ReadSpec();
  fuzz::RequireMessage(spec.status());
  if (!spec.ok()) return 0;
  absl::StatusOr<SimplifyOptions> options = wire::FromProto(spec->options(), 2, 2);
  fuzz::RequireMessage(options.status());
  if (!options.ok()) return 0;
  if (spec->fe_check()) {
    fuzz::RequireMessage(wire::FeCheckOptionsFromProto(spec->fe_check_options()).status());
  }
  absl::StatusOr<RawMesh> mesh = reader.ReadMesh(*spec);
  fuzz::RequireMessage(mesh.status());
  if (mesh.ok()) fuzz::Prepare(*std::move(mesh), options->repair);
  return 0;
}
