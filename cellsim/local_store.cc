#include "cellsim/local_store.h"

#include <algorithm>
#include <new>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {
namespace {
// Alignment of the arena itself: large enough for any cache line size we accept.
constexpr size_t kArenaAlignment = 16 * 1024;
}  // namespace

void LocalStore::AlignedDelete::operator()(std::byte* p) const {
  ::operator delete[](p, std::align_val_t{kArenaAlignment});
}

absl::StatusOr<std::unique_ptr<LocalStore>> LocalStore::Create(size_t bytes) {
  if (bytes == 0 || bytes % 16 != 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("local store size must be a positive multiple of 16 bytes, got %d", bytes));
  }
  auto* base = static_cast<std::byte*>(::operator new[](bytes, std::align_val_t{kArenaAlignment}));
  return std::unique_ptr<LocalStore>(new LocalStore(base, bytes));
}

absl::StatusOr<std::byte*> LocalStore::Allocate(size_t bytes, size_t alignment,
                                                std::string_view what) {
  if (alignment < 16 || (alignment & (alignment - 1)) != 0 || alignment > kArenaAlignment) {
    return absl::InvalidArgumentError(
        absl::StrFormat("local store: alignment %d for '%s' must be a power of two in [16, %d]",
                        alignment, what, kArenaAlignment));
  }
  const size_t start = (used_ + alignment - 1) & ~(alignment - 1);
  if (start > capacity_ || bytes > capacity_ - start) {
    return absl::ResourceExhaustedError(absl::StrFormat(
        "local store: cannot allocate %d bytes for '%s' (aligned to %d): %d of %d bytes left",
        bytes, what, alignment, available(), capacity_));
  }
  used_ = start + bytes;
  high_water_ = std::max(high_water_, used_);
  return base_.get() + start;
}

}  // namespace femsimp::cellsim
