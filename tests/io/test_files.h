// Shared helpers for the I/O tests: a per-test temporary directory and small meshes.
#pragma once

#include <string>

#include "engine/raw_mesh.h"
#include "gtest/gtest.h"

namespace femsimp::testing {

// Gives each test an empty directory of its own, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  // Writes `contents` (text or bytes) to `name` in the directory and returns its path.
  std::string Write(const std::string& name, const std::string& contents);
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  std::string dir_;
};

// A closed tetrahedron, counter-clockwise seen from outside, with coordinates that need all
// nine significant digits of a float.
RawMesh Tetrahedron();

std::string TestDataPath(const std::string& name);

}  // namespace femsimp::testing
