// Conversions between the engine's types and femsimp.v1 messages, and mesh chunking; shared
// by the server and the remote client so both sides agree on the wire format.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "engine/raw_mesh.h"
#include "engine/simplify.h"
#include "femsimp/v1/femsimp.pb.h"

namespace femsimp::wire {

// Per-chunk sizes: 64 Ki vertices (768 KiB) + 64 Ki faces (768 KiB + 256 KiB groups + 256 KiB
// per field) keeps a message under 2.6 MiB, well under gRPC's default 4 MiB limit.
inline constexpr size_t kChunkVertices = 64 * 1024;
inline constexpr size_t kChunkFaces = 64 * 1024;

// Both directions go over the option table (engine/option_table.h), field by field by name.
// threads_given = false leaves EngineOptions.threads at 0 (server default); the cell options
// are sent only for the cell back end.
void ToProto(const SimplifyOptions& o, bool threads_given, v1::EngineOptions* out);
// Unset fields take the engine defaults (a field without presence is unset when 0); threads 0
// -> default_threads, capped at max_threads; the cell options are read only for the cell back
// end. Runs ValidateOptions, so errors name the parameter and its range in the table's words.
absl::StatusOr<SimplifyOptions> FromProto(const v1::EngineOptions& in, int default_threads,
                                          int max_threads);

void ToProto(const PassStats& p, v1::Progress* out);
PassStats FromProto(const v1::Progress& in);

// The fidelity figures of a result (feature_edges .. max_field_change); the other members of
// v1::Result come from the server's job, not from SimplifyResult alone.
void FidelityToProto(const SimplifyResult& r, v1::Result* out);
void FidelityFromProto(const v1::Result& in, SimplifyResult* out);

// The repair report of a result, both ways (kinds by their names, RepairKindName).
void RepairToProto(const RepairReport& r, v1::RepairReport* out);
RepairReport RepairFromProto(const v1::RepairReport& in);

// Face field names of a spec or result: at most kMaxFaceFields, distinct, 1 to 64 bytes each.
// `where` prefixes the message, e.g. "spec: face_field_names".
inline constexpr size_t kMaxFieldNameBytes = 64;
absl::Status CheckFieldNames(const google::protobuf::RepeatedPtrField<std::string>& names,
                             const std::string& where);
std::vector<std::string> FieldNames(const RawMesh& mesh);

const char* BackendName(Backend b);

// How many chunks ForEachChunk cuts the mesh into, and chunk k of them (k < ChunkCount), so that
// a caller may encode one chunk while it sends another.
size_t ChunkCount(const RawMesh& mesh, size_t chunk_vertices = kChunkVertices,
                  size_t chunk_faces = kChunkFaces);
void FillChunk(const RawMesh& mesh, size_t k, v1::MeshChunk* chunk,
               size_t chunk_vertices = kChunkVertices, size_t chunk_faces = kChunkFaces);

// Calls emit for each chunk of the mesh, in order; stops early when emit returns false.
// Returns the number of chunks emitted.
size_t ForEachChunk(const RawMesh& mesh, const std::function<bool(v1::MeshChunk&)>& emit,
                    size_t chunk_vertices = kChunkVertices, size_t chunk_faces = kChunkFaces);

// Collects chunks up to declared counts, checking each chunk as it arrives: whole vertices
// and faces, nothing past the declared counts, finite coordinates and field values, indices
// below the declared vertex count, one value array per declared field. Messages name the
// problem and where (chunk number, vertex or face index, field name). The field names are
// checked by the caller (CheckFieldNames).
// A spec's or result's origin (RawMesh::origin): empty, or three finite coordinates; `where`
// prefixes the message, e.g. "spec: origin". ToProto leaves origin 0 empty.
absl::StatusOr<std::array<double, 3>> OriginFromProto(
    const google::protobuf::RepeatedField<double>& origin, const std::string& where);
void OriginToProto(const std::array<double, 3>& origin,
                   google::protobuf::RepeatedField<double>* out);

class MeshAssembler {
 public:
  MeshAssembler(uint64_t vertices, uint64_t faces, bool face_groups,
                std::vector<std::string> field_names = {},
                const std::array<double, 3>& origin = {});
  absl::Status Add(const v1::MeshChunk& chunk);
  // Fails when arrays are short of the declared counts.
  absl::StatusOr<RawMesh> Finish();
  uint64_t chunks() const { return chunks_; }

 private:
  uint64_t vertices_, faces_;
  bool face_groups_;
  uint64_t chunks_ = 0;
  RawMesh mesh_;
};

}  // namespace femsimp::wire
