// Writes seeds for request_fuzzer: each mesh file named is read and sent as the client sends it
// (client/remote_call.cc: the spec, then the chunks of wire::ForEachChunk, here a few vertices
// and faces per chunk so that a small mesh makes several), framed as request_fuzzer reads them.
// Three variants per file: the default options, repair off with the cell back end, and an FE
// check with its options.
//   make_request_seeds OUT_DIR MESH_FILE...
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "engine/io/mesh_readers.h"
#include "femsimp/v1/femsimp.pb.h"
#include "google/protobuf/io/coded_stream.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"
#include "proto/wire.h"

namespace {

void Put(const femsimp::v1::SimplifyRequest& r, std::string* out) {
  google::protobuf::io::StringOutputStream stream(out);
  google::protobuf::io::CodedOutputStream coded(&stream);
  const std::string bytes = r.SerializeAsString();
  coded.WriteVarint32(static_cast<uint32_t>(bytes.size()));
  coded.WriteString(bytes);
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_request_seeds OUT_DIR MESH_FILE...\n");
    return 2;
  }
  const fs::path out_dir = argv[1];
  fs::create_directories(out_dir);
  for (int i = 2; i < argc; ++i) {
    const fs::path path = argv[i];
    std::ifstream f(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    absl::StatusOr<femsimp::ParsedMeshFile> parsed =
        femsimp::ParseMeshFile(path.extension().string(), bytes);
    if (!parsed.ok()) {
      std::fprintf(stderr, "%s: %s\n", argv[i], std::string(parsed.status().message()).c_str());
      return 1;
    }
    const femsimp::RawMesh& mesh = parsed->mesh;
    for (int variant = 0; variant < 3; ++variant) {
      femsimp::v1::SimplifyRequest spec_message;
      femsimp::v1::JobSpec& spec = *spec_message.mutable_spec();
      spec.set_vertex_count(mesh.num_vertices());
      spec.set_face_count(mesh.num_faces());
      spec.set_has_face_groups(!mesh.face_groups.empty());
      for (const femsimp::FaceField& field : mesh.face_fields)
        spec.add_face_field_names(field.name);
      spec.set_client_label("seed");
      femsimp::v1::EngineOptions& options = *spec.mutable_options();
      options.set_ratio(0.5);
      if (variant == 1) {
        options.set_repair(femsimp::v1::REPAIR_MODE_OFF);
        options.set_backend(femsimp::v1::BACKEND_CELL);
        options.mutable_cell()->set_spes(2);
      } else if (variant == 2) {
        spec.set_fe_check(true);
        spec.mutable_fe_check_options()->set_modes(3);
      }
      std::string seed;
      Put(spec_message, &seed);
      femsimp::wire::ForEachChunk(
          mesh,
          [&seed](femsimp::v1::MeshChunk& chunk) {
            femsimp::v1::SimplifyRequest r;
            *r.mutable_chunk() = chunk;
            Put(r, &seed);
            return true;
          },
          4, 4);
      const fs::path out =
          out_dir / (path.filename().string() + "." + std::to_string(variant) + ".bin");
      std::ofstream(out, std::ios::binary) << seed;
    }
  }
  return 0;
}
