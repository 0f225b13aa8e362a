// An allocator for the large arrays that the kernel walks in no spatial order (the mesh's
// quadwords): an array of 2 MiB or more is aligned to 2 MiB and advised to be backed by huge
// pages (Linux transparent huge pages; in their "madvise" mode, this machine's, only advised
// memory gets them), so that ring walks over a mesh of hundreds of MB miss the TLB far less
// (docs/BENCHMARKS.md, "Huge pages"). The advice changes no result; where the kernel declines it
// the pages stay 4 KiB. Smaller arrays come from the heap as usual.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <vector>

namespace femsimp {

inline constexpr size_t kHugePageBytes = size_t{2} << 20;

template <class T>
class HugePageAllocator {
 public:
  using value_type = T;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    if (n > SIZE_MAX / sizeof(T)) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
    if (bytes < kHugePageBytes) return std::allocator<T>().allocate(n);
    void* p = ::operator new (Rounded(bytes), std::align_val_t{kHugePageBytes});
#ifdef MADV_HUGEPAGE
    ::madvise(p, Rounded(bytes), MADV_HUGEPAGE);  // advice: its failure only leaves small pages
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) noexcept {
    if (n * sizeof(T) < kHugePageBytes)
      std::allocator<T>().deallocate(p, n);
    else
      ::operator delete (p, std::align_val_t{kHugePageBytes});
  }

  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }

 private:
  static size_t Rounded(size_t bytes) {
    return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  }
};

// A vector whose storage HugePageAllocator provides.
template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

// A fixed array the same way, for elements a vector cannot hold (atomics).
template <class T>
class HugePageArrayDeleter {
 public:
  HugePageArrayDeleter() = default;
  explicit HugePageArrayDeleter(size_t n) : n_(n) {}
  void operator()(T* p) const {
    std::destroy_n(p, n_);
    HugePageAllocator<T>().deallocate(p, n_);
  }

 private:
  size_t n_ = 0;
};
template <class T>
using HugePageArray = std::unique_ptr<T[], HugePageArrayDeleter<T>>;

// n elements, value-initialised (zeroed where T is trivial), as std::make_unique<T[]>.
template <class T>
HugePageArray<T> MakeHugePageArray(size_t n) {
  T* p = HugePageAllocator<T>().allocate(n);
  std::uninitialized_value_construct_n(p, n);
  return HugePageArray<T>(p, HugePageArrayDeleter<T>(n));
}
// n elements, default-initialised, as std::make_unique_for_overwrite<T[]>.
template <class T>
HugePageArray<T> MakeHugePageArrayForOverwrite(size_t n) {
  T* p = HugePageAllocator<T>().allocate(n);
  std::uninitialized_default_construct_n(p, n);
  return HugePageArray<T>(p, HugePageArrayDeleter<T>(n));
}

}  // namespace femsimp
