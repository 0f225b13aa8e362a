#include "tests/io/test_files.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace femsimp::testing {

void TempDirTest::SetUp() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(info->test_suite_name()) + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';  // parameterized test names contain slashes
  dir_ = (std::filesystem::temp_directory_path() /
          ("femsimp_io_" + std::to_string(getpid()) + "_" + name))
             .string();
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
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

RawMesh Tetrahedron() {
  RawMesh m;
  m.positions = {0.1f,        -0.2f,          1.0f / 3.0f,   //
                 123.456789f, 1.23456789e-6f, 0.3f,          //
                 0.7f,        45.6f,          -2.0f / 7.0f,  //
                 3.14159265f, 2.5f,           -98.7654321f};
  // Oriented so that every face is counter-clockwise seen from outside.
  m.triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  return m;
}

std::string TestDataPath(const std::string& name) {
  return std::string(FEMSIMP_TEST_DATA) + "/" + name;
}

}  // namespace femsimp::testing
