// A private temporary directory for one run of the FE check's tools, removed with everything in
// it when the object goes (on success, error and cancel alike).
#pragma once

#include <string>

#include "absl/status/statusor.h"

namespace femsimp::fecheck {

class TempDir {
 public:
  // A new directory "femsimp-fecheck-XXXXXX" under $TMPDIR (or /tmp).
  static absl::StatusOr<TempDir> Create();
  TempDir(TempDir&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }
  TempDir& operator=(TempDir&&) = delete;
  TempDir(const TempDir&) = delete;
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string File(const std::string& name) const { return path_ + "/" + name; }

 private:
  explicit TempDir(std::string path) : path_(std::move(path)) {}
  std::string path_;
};

}  // namespace femsimp::fecheck
