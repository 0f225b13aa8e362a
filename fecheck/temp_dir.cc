#include "fecheck/temp_dir.h"

#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "absl/strings/str_cat.h"

namespace femsimp::fecheck {

absl::StatusOr<TempDir> TempDir::Create() {
  std::error_code ec;
  const std::filesystem::path base = std::filesystem::temp_directory_path(ec);
  std::string pattern = absl::StrCat(ec ? "/tmp" : base.string(), "/femsimp-fecheck-XXXXXX");
  if (mkdtemp(pattern.data()) == nullptr)
    return absl::InternalError(
        absl::StrCat("cannot create a temporary directory ", pattern, ": ", strerror(errno)));
  return TempDir(std::move(pattern));
}

TempDir::~TempDir() {
  if (path_.empty()) return;
  std::error_code ignored;  // nothing to report from a destructor; the path is ours alone
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace femsimp::fecheck
