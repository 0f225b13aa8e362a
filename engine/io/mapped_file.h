// A mesh file's bytes, memory-mapped: the readers parse the page cache in place instead of a copy
// (one pass over the file, no buffer as large as the file). Files that cannot be mapped (pipes,
// character devices, empty files) are read into memory instead, with the same errors.
#pragma once

#include <cstddef>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace femsimp {

class MappedFile {
 public:
  // Errors name the path: NotFound (no such file), PermissionDenied (cannot open for reading),
  // FailedPrecondition (a directory, a path that cannot be searched, a read or map error).
  static absl::StatusOr<MappedFile> Open(const std::string& path);

  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();

  absl::string_view data() const { return {data_, size_}; }

 private:
  MappedFile() = default;
  void Release();

  const char* data_ = nullptr;
  size_t size_ = 0;
  bool mapped_ = false;  // data_ is an mmap of size_ bytes, else it points into copy_
  std::string copy_;
};

}  // namespace femsimp
