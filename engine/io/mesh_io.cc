#include "engine/io/mesh_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "engine/io/mapped_file.h"
#include "engine/io/mesh_readers.h"
#include "engine/io/msh.h"

namespace femsimp {
namespace {

namespace fs = std::filesystem;

// A float needs 9 significant digits to survive a text round trip exactly (max_digits10).

std::string LowerExtension(const std::string& path) {
  return absl::AsciiStrToLower(fs::path(path).extension().string());
}

absl::Status CheckExtension(const std::string& path, const std::string& ext) {
  const auto& ok = SupportedMeshExtensions();
  if (std::find(ok.begin(), ok.end(), ext) != ok.end()) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(path, ": unsupported mesh file extension '", ext,
                                                 "' (supported: ", absl::StrJoin(ok, ", "), ")"));
}

absl::Status Prefixed(const std::string& path, const absl::Status& s) {
  return absl::Status(s.code(), absl::StrCat(path, ": ", s.message()));
}

absl::Status OpenFailure(const std::string& path) {
  const int err = errno;
  const std::string why = absl::StrCat(path, ": cannot open for writing: ", std::strerror(err));
  return err == EACCES ? absl::PermissionDeniedError(why) : absl::FailedPreconditionError(why);
}

absl::Status WriteMesh(const std::string& path, const RawMesh& mesh, bool binary,
                       const GroupNames& group_names) {
  const std::string ext = LowerExtension(path);
  if (absl::Status s = CheckExtension(path, ext); !s.ok()) return s;
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0 ||
      (!mesh.face_groups.empty() && mesh.face_groups.size() != nf))
    return absl::InvalidArgumentError(
        absl::StrCat(path, ": malformed soup: ", mesh.positions.size(), " coordinates, ",
                     mesh.triangles.size(), " indices, ", mesh.face_groups.size(), " face groups"));
  for (const FaceField& field : mesh.face_fields)
    if (field.values.size() != nf)
      return absl::InvalidArgumentError(absl::StrCat(path, ": malformed soup: face field '",
                                                     field.name, "' has ", field.values.size(),
                                                     " values for ", nf, " faces"));
  if (absl::Status s = CheckFormatHolds(ext, mesh); !s.ok()) return Prefixed(path, s);
  if (absl::Status s = CheckFaceData(ext, mesh, group_names); !s.ok()) return Prefixed(path, s);

  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec))
    return absl::NotFoundError(
        absl::StrCat(path, ": directory '", parent.string(), "' does not exist"));

  // Indices must be in range; anything else is written as it is (the output of an assembly
  // keeps its seams, edges of three or more faces; tests write broken files on purpose).
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &mesh.triangles[3 * f];
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv)
      return absl::InvalidArgumentError(
          absl::StrCat(path, ": face ", f, " references a vertex past ", nv));
  }

  const std::string bytes = ext == ".obj"   ? ObjText(mesh, group_names)
                            : ext == ".ply" ? PlyBytes(mesh, binary)
                            : ext == ".msh" ? MshText(mesh, group_names)
                            : ext == ".off" ? OffText(mesh)
                                            : StlBytes(mesh, binary, group_names);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return OpenFailure(path);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out)
    return absl::DataLossError(
        absl::StrCat(path, ": write failed after opening (", bytes.size(), " bytes)"));
  return absl::OkStatus();
}

}  // namespace

const std::vector<std::string>& SupportedMeshExtensions() {
  static const std::vector<std::string> kExt = {".off", ".obj", ".stl", ".ply", ".msh"};
  return kExt;
}

absl::StatusOr<RawMesh> ReadMeshFile(const std::string& path, GroupNames* group_names,
                                     std::vector<std::string>* warnings) {
  const std::string ext = LowerExtension(path);
  if (absl::Status s = CheckExtension(path, ext); !s.ok()) return s;
  absl::StatusOr<MappedFile> file = MappedFile::Open(path);
  if (!file.ok()) return file.status();
  if (file->data().empty())
    return absl::InvalidArgumentError(absl::StrCat(path, ": file is empty"));
  absl::StatusOr<ParsedMeshFile> parsed = absl::InternalError("not parsed");
  if (absl::Status read =
          file->Read([&](absl::string_view bytes) { parsed = ParseMeshFile(ext, bytes); });
      !read.ok())
    return read;
  if (!parsed.ok()) return Prefixed(path, parsed.status());
  if (group_names) *group_names = std::move(parsed->group_names);
  if (warnings) *warnings = std::move(parsed->warnings);
  return std::move(parsed->mesh);
}

absl::Status WriteMeshFile(const std::string& path, const RawMesh& mesh,
                           const GroupNames& group_names) {
  return WriteMesh(path, mesh, /*binary=*/true, group_names);
}

absl::Status WriteMeshFileAscii(const std::string& path, const RawMesh& mesh,
                                const GroupNames& group_names) {
  return WriteMesh(path, mesh, /*binary=*/false, group_names);
}

std::string MeshFileExtension(const std::string& path) { return LowerExtension(path); }

}  // namespace femsimp
