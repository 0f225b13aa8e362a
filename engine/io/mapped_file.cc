#include "engine/io/mapped_file.h"

#include <fcntl.h>
#include <setjmp.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
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

// MappedFile::Read on this thread: the mapping it reads and where to return to on SIGBUS.
thread_local sigjmp_buf* t_return = nullptr;
thread_local const char* t_begin = nullptr;
thread_local const char* t_end = nullptr;
struct sigaction g_previous_sigbus;

// A SIGBUS in a mapping a Read is reading goes back to that Read; any other goes to the handler
// there was before (or ends the process as it would have).
void OnSigbus(int signal, siginfo_t* info, void* context) {
  const char* at = static_cast<const char*>(info->si_addr);
  if (t_return != nullptr && at >= t_begin && at < t_end) siglongjmp(*t_return, 1);
  if (g_previous_sigbus.sa_flags & SA_SIGINFO) {
    g_previous_sigbus.sa_sigaction(signal, info, context);
  } else if (g_previous_sigbus.sa_handler != SIG_DFL && g_previous_sigbus.sa_handler != SIG_IGN) {
    g_previous_sigbus.sa_handler(signal);
  } else {
    ::signal(SIGBUS, SIG_DFL);
    ::raise(SIGBUS);
  }
}

void InstallSigbusHandler() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction action {};
    action.sa_sigaction = OnSigbus;
    action.sa_flags = SA_SIGINFO;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGBUS, &action, &g_previous_sigbus);
  });
}

}  // namespace

absl::Status MappedFile::Read(const std::function<void(absl::string_view)>& read) const {
  if (!mapped_) {
    read(data());
    return absl::OkStatus();
  }
  InstallSigbusHandler();
  sigjmp_buf back;
  t_begin = data_;
  t_end = data_ + size_;
  t_return = &back;
  if (sigsetjmp(back, /*savemask=*/1) == 0) {
    read(data());
    t_return = nullptr;
    return absl::OkStatus();
  }
  t_return = nullptr;
  struct stat now;
  const std::string size_now =
      ::stat(path_.c_str(), &now) == 0 ? absl::StrCat(", ", now.st_size, " now") : "";
  return absl::FailedPreconditionError(
      absl::StrCat(path_, ": the file shrank while it was read (", size_, " bytes when opened",
                   size_now, "): another program wrote it; read it again once it is complete"));
}

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
  file.path_ = path;
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
  path_ = std::move(other.path_);
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
