// A mesh file's bytes, memory-mapped: the readers parse the page cache in place instead of a copy
// (one pass over the file, no buffer as large as the file). Files that cannot be mapped (pipes,
// character devices, empty files) are read into memory instead, with the same errors.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "absl/status/status.h"
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
  // Runs read(data()) on this thread. A mapped file that another process truncates meanwhile
  // loses the pages past its new end, and reading them raises SIGBUS: read is then abandoned
  // where it was (what it allocated is not freed) and the result is FailedPrecondition, naming
  // the path, instead of the end of the process.
  absl::Status Read(const std::function<void(absl::string_view)>& read) const;

 private:
  MappedFile() = default;
  void Release();

  std::string path_;
  const char* data_ = nullptr;
  size_t size_ = 0;
  bool mapped_ = false;  // data_ is an mmap of size_ bytes, else it points into copy_
  std::string copy_;
};

}  // namespace femsimp
