#include "tests/support/files.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

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
