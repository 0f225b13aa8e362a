// A per-test temporary directory, files in it, and mesh files written and read back per format.
#pragma once

#include <string>

#include "engine/raw_mesh.h"
#include "gtest/gtest.h"

namespace femsimp::testing {

// An empty directory named after `name` and the process, under the system's temporary
// directory (removed first if it exists).
std::string MakeTempDir(const std::string& name);

// The whole file (empty if it cannot be read).
std::string ReadFileBytes(const std::string& path);

// Gives each test an empty directory of its own, removed afterwards unless the test failed.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  // Writes `contents` (text or bytes) to `name` in the directory and returns its path.
  std::string Write(const std::string& name, const std::string& contents);
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  // Writes the soup as it is, defects included (the library's writers refuse some), as text in
  // the format of the name's extension (.off, .obj, .stl, .ply); returns its path.
  std::string WriteSoup(const std::string& name, const RawMesh& mesh);

  std::string dir_;
};

// A mesh file format, and whether it is written as text.
struct FileFormat {
  std::string ext;
  bool ascii;
};
std::string FileFormatName(const ::testing::TestParamInfo<FileFormat>& info);  // e.g. "ply_ascii"

// A test per format: RoundTrip writes a mesh in the format and reads it back.
class FileFormatTest : public TempDirTest, public ::testing::WithParamInterface<FileFormat> {
 protected:
  RawMesh RoundTrip(const RawMesh& in);
};

}  // namespace femsimp::testing
