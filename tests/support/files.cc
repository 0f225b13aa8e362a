#include "tests/support/files.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/io/mesh_io.h"

namespace femsimp::testing {

std::string MakeTempDir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("femsimp_" + std::to_string(getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void TempDirTest::SetUp() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(info->test_suite_name()) + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';  // parameterized test names contain slashes
  dir_ = MakeTempDir(name);
}

void TempDirTest::TearDown() {
  if (!HasFailure()) std::filesystem::remove_all(dir_);  // keep the files of a failing test
}

std::string TempDirTest::WriteSoup(const std::string& name, const RawMesh& m) {
  const std::string ext = name.substr(name.rfind('.'));
  const auto point = [&](uint32_t v) {
    return absl::StrFormat("%.9g %.9g %.9g", m.positions[3 * v], m.positions[3 * v + 1],
                           m.positions[3 * v + 2]);
  };
  std::string s;
  if (ext == ".stl") {
    s = "solid soup\n";
    for (size_t f = 0; f < m.num_faces(); ++f) {
      s += "facet normal 0 0 0\nouter loop\n";
      for (int k = 0; k < 3; ++k) s += absl::StrCat("vertex ", point(m.triangles[3 * f + k]), "\n");
      s += "endloop\nendfacet\n";
    }
    return Write(name, s + "endsolid soup\n");
  }
  if (ext == ".off") s = absl::StrCat("OFF\n", m.num_vertices(), " ", m.num_faces(), " 0\n");
  if (ext == ".ply")
    s = absl::StrCat("ply\nformat ascii 1.0\nelement vertex ", m.num_vertices(),
                     "\nproperty float x\nproperty float y\nproperty float z\nelement face ",
                     m.num_faces(), "\nproperty list uchar int vertex_indices\nend_header\n");
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    s += absl::StrCat(ext == ".obj" ? "v " : "", point(v), "\n");
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const uint32_t* t = &m.triangles[3 * f];
    const uint32_t base = ext == ".obj" ? 1 : 0;
    s += absl::StrCat(ext == ".obj" ? "f" : "3", " ", t[0] + base, " ", t[1] + base, " ",
                      t[2] + base, "\n");
  }
  return Write(name, s);
}

std::string TempDirTest::Write(const std::string& name, const std::string& contents) {
  const std::string path = Path(name);
  std::ofstream out(path, std::ios::binary);
  out << contents;
  EXPECT_TRUE(out.good()) << path;
  return path;
}

std::string FileFormatName(const ::testing::TestParamInfo<FileFormat>& info) {
  return info.param.ext.substr(1) + (info.param.ascii ? "_ascii" : "_binary");
}

RawMesh FileFormatTest::RoundTrip(const RawMesh& in) {
  const std::string path = Path("mesh" + GetParam().ext);
  absl::Status written = GetParam().ascii ? WriteMeshFileAscii(path, in) : WriteMeshFile(path, in);
  EXPECT_TRUE(written.ok()) << written;
  absl::StatusOr<RawMesh> out = ReadMeshFile(path);
  EXPECT_TRUE(out.ok()) << out.status();
  return out.ok() ? *std::move(out) : RawMesh{};
}

}  // namespace femsimp::testing
