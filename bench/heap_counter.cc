#include "bench/heap_counter.h"

#include <malloc.h>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {

std::atomic<int64_t> g_live{0}, g_peak{0};

void Count(void* p) {
  if (!p) throw std::bad_alloc();
  const auto size = static_cast<int64_t>(malloc_usable_size(p));
  const int64_t n = g_live.fetch_add(size) + size;
  int64_t peak = g_peak.load(std::memory_order_relaxed);
  while (n > peak && !g_peak.compare_exchange_weak(peak, n, std::memory_order_relaxed)) {
  }
}
void Uncount(void* p) {
  if (p) g_live.fetch_sub(static_cast<int64_t>(malloc_usable_size(p)));
}
void* Aligned(size_t n, std::align_val_t a) {
  const size_t al = static_cast<size_t>(a);
  void* p = std::aligned_alloc(al, (n + al - 1) / al * al);
  Count(p);
  return p;
}

}  // namespace

namespace femsimp::bench {

int64_t LiveHeapBytes() { return g_live.load(); }
int64_t PeakHeapBytes() { return g_peak.load(); }
void ResetHeapPeak() { g_peak.store(g_live.load()); }

}  // namespace femsimp::bench

void* operator new(size_t n) {
  void* p = std::malloc(n ? n : 1);
  Count(p);
  return p;
}
void* operator new[](size_t n) { return operator new(n); }
void* operator new(size_t n, std::align_val_t a) { return Aligned(n, a); }
void* operator new[](size_t n, std::align_val_t a) { return Aligned(n, a); }
void operator delete(void* p) noexcept {
  Uncount(p);
  std::free(p);
}
void operator delete[](void* p) noexcept { operator delete(p); }
void operator delete(void* p, size_t) noexcept { operator delete(p); }
void operator delete[](void* p, size_t) noexcept { operator delete(p); }
void operator delete(void* p, std::align_val_t) noexcept { operator delete(p); }
void operator delete[](void* p, std::align_val_t) noexcept { operator delete(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { operator delete(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { operator delete(p); }
// The nothrow forms too (std::stable_sort's buffer, OpenMesh, CGAL): a sanitizer runtime defines
// every form it is not given, and its blocks would come back here to free().
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  void* p = std::malloc(n ? n : 1);
  if (p != nullptr) Count(p);
  return p;
}
void* operator new[](size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void* operator new(size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  const size_t al = static_cast<size_t>(a);
  void* p = std::aligned_alloc(al, (n + al - 1) / al * al);
  if (p != nullptr) Count(p);
  return p;
}
void* operator new[](size_t n, std::align_val_t a, const std::nothrow_t& t) noexcept {
  return operator new(n, a, t);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { operator delete(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { operator delete(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  operator delete(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  operator delete(p);
}
