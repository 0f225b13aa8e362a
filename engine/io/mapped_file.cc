#include "engine/io/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace femsimp {
namespace {

namespace fs = std::filesystem;

// Closes the descriptor on every way out of Open.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

absl::Status ReadError(const std::string& path, size_t done, int err) {
  return absl::FailedPreconditionError(
      absl::StrCat(path, ": read error after ", done, " bytes: ", std::strerror(err)));
}

}  // namespace

absl::StatusOr<MappedFile> MappedFile::Open(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found)
    return absl::NotFoundError(absl::StrCat(path, ": no such file"));
  if (ec)  // e.g. a parent directory that cannot be searched
    return absl::FailedPreconditionError(absl::StrCat(path, ": cannot access: ", ec.message()));
  if (fs::is_directory(st))
    return absl::FailedPreconditionError(absl::StrCat(path, ": is a directory, not a mesh file"));
  const Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) {
    const int err = errno;
    const std::string why = absl::StrCat(path, ": cannot open for reading: ", std::strerror(err));
    return err == EACCES ? absl::PermissionDeniedError(why) : absl::FailedPreconditionError(why);
  }
  MappedFile file;
  struct stat info;
  if (::fstat(fd.get(), &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0) {
    // MAP_POPULATE faults the whole file in with one call instead of a fault per page.
    void* p =
        ::mmap(nullptr, size_t(info.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd.get(), 0);
    if (p != MAP_FAILED) {
      ::madvise(p, size_t(info.st_size), MADV_SEQUENTIAL);
      file.data_ = static_cast<const char*>(p);
      file.size_ = size_t(info.st_size);
      file.mapped_ = true;
      return file;
    }
  }
  // Not a regular file (a pipe, /dev/stdin), empty, or not mappable: read it to its end.
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd.get(), buffer, sizeof(buffer));
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      return ReadError(path, file.copy_.size(), errno);
    }
    file.copy_.append(buffer, size_t(n));
  }
  file.data_ = file.copy_.data();
  file.size_ = file.copy_.size();
  return file;
}

MappedFile::MappedFile(MappedFile&& other) noexcept { *this = std::move(other); }

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
  if (this == &other) return *this;
  Release();
  mapped_ = std::exchange(other.mapped_, false);
  size_ = std::exchange(other.size_, 0);
  copy_ = std::move(other.copy_);
  data_ = mapped_ ? std::exchange(other.data_, nullptr) : copy_.data();
  other.data_ = nullptr;
  return *this;
}

MappedFile::~MappedFile() { Release(); }

void MappedFile::Release() {
  if (mapped_) ::munmap(const_cast<char*>(data_), size_);
  mapped_ = false;
  data_ = nullptr;
  size_ = 0;
  copy_.clear();
}

}  // namespace femsimp
