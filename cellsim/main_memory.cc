#include "cellsim/main_memory.h"

#include <algorithm>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {

absl::Status MainMemory::Register(const void* base, size_t bytes, std::string name) {
  const uint64_t begin = Ea(base);
  if (base == nullptr || bytes == 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("main memory region '%s': null base or zero size", name));
  }
  if (begin % 4 != 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("main memory region '%s': base 0x%x is not 4-byte aligned", name, begin));
  }
  const uint64_t end = begin + bytes;
  for (const Region& r : regions_) {
    if (begin < r.end && r.begin < end) {
      return absl::AlreadyExistsError(
          absl::StrFormat("main memory region '%s' [0x%x, 0x%x) overlaps region '%s' [0x%x, 0x%x)",
                          name, begin, end, r.name, r.begin, r.end));
    }
  }
  Region region{begin, end, std::move(name)};
  auto it = std::upper_bound(regions_.begin(), regions_.end(), begin,
                             [](uint64_t b, const Region& r) { return b < r.begin; });
  regions_.insert(it, std::move(region));
  return absl::OkStatus();
}

absl::Status MainMemory::Unregister(const void* base) {
  auto it = std::find_if(regions_.begin(), regions_.end(),
                         [&](const Region& r) { return r.begin == Ea(base); });
  if (it == regions_.end()) {
    return absl::NotFoundError(absl::StrFormat("no main memory region starts at 0x%x", Ea(base)));
  }
  regions_.erase(it);
  return absl::OkStatus();
}

const MainMemory::Region* MainMemory::Find(uint64_t ea, size_t size) const {
  // Few regions (a mesh has a handful of arrays): a binary search is plenty.
  auto it = std::upper_bound(regions_.begin(), regions_.end(), ea,
                             [](uint64_t a, const Region& r) { return a < r.begin; });
  if (it == regions_.begin()) return nullptr;
  --it;
  if (ea >= it->begin && ea + size <= it->end && ea + size >= ea) return &*it;
  return nullptr;
}

absl::Status MainMemory::Check(uint64_t ea, size_t size, const char* what) const {
  if (Find(ea, size) != nullptr) return absl::OkStatus();
  return absl::OutOfRangeError(absl::StrFormat(
      "%s: main memory range [0x%x, 0x%x) is not inside one registered region (%d registered)",
      what, ea, ea + size, regions_.size()));
}

}  // namespace femsimp::cellsim
