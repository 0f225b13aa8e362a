#ifndef FEMSIMP_CELLSIM_LOCAL_STORE_H_
#define FEMSIMP_CELLSIM_LOCAL_STORE_H_

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "absl/status/statusor.h"

namespace femsimp::cellsim {

// The private memory of one SPE (256 KiB on the Cell BE). Everything the SPE works on lives in
// it: software cache lines and tags, software-thread stacks and control blocks, DMA buffers,
// scratch. A bump allocator: allocations are never freed one by one, but Mark()/Release() give
// stack-like scopes (RunThreads uses one for its stacks). The budget is the point: an
// allocation that does not fit fails instead of silently using host memory.
//
// DMA only accepts local-store addresses inside this arena (as the MFC only accepts LS
// addresses), so a kernel that runs outside RunThreads must allocate its DMA buffers here;
// inside RunThreads its stack variables already live here.
class LocalStore {
 public:
  static constexpr size_t kDefaultBytes = 256 * 1024;

  // `bytes` must be a positive multiple of 16.
  static absl::StatusOr<std::unique_ptr<LocalStore>> Create(size_t bytes = kDefaultBytes);

  // `bytes` from the budget, aligned to `alignment` (a power of two, at least 16). `what`
  // names the buffer in the error when it does not fit.
  absl::StatusOr<std::byte*> Allocate(size_t bytes, size_t alignment = 16,
                                      std::string_view what = "buffer");

  using Marker = size_t;
  Marker Mark() const { return used_; }
  // Frees everything allocated since `m` was taken.
  void Release(Marker m) {
    if (m <= used_) used_ = m;
  }

  bool Contains(const void* p, size_t bytes) const {
    const auto a = reinterpret_cast<uintptr_t>(p);
    const auto b = reinterpret_cast<uintptr_t>(base_.get());
    return a >= b && a - b <= capacity_ && bytes <= capacity_ - (a - b);
  }
  std::byte* base() const { return base_.get(); }
  size_t capacity() const { return capacity_; }
  size_t used() const { return used_; }
  size_t available() const { return capacity_ - used_; }
  size_t high_water() const { return high_water_; }

 private:
  struct AlignedDelete {
    void operator()(std::byte* p) const;
  };
  LocalStore(std::byte* base, size_t capacity) : base_(base), capacity_(capacity) {}

  std::unique_ptr<std::byte[], AlignedDelete> base_;
  size_t capacity_;
  size_t used_ = 0;
  size_t high_water_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_LOCAL_STORE_H_
