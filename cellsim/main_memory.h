#ifndef FEMSIMP_CELLSIM_MAIN_MEMORY_H_
#define FEMSIMP_CELLSIM_MAIN_MEMORY_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"

namespace femsimp::cellsim {

// An effective address (EA) in main memory. Main memory is host memory: the EA of an object is
// its host address.
inline uint64_t Ea(const void* p) { return reinterpret_cast<uintptr_t>(p); }

// The regions of host memory that the SPEs may reach by DMA, the software cache and the atomic
// unit (like the mappings of the PPE process on the real machine). A request outside every
// region fails, and a cache line is only filled with the part that lies inside the region of
// the address read, so a line never reads past the end of an array.
//
// Register regions from the PPE side between runs (Runtime::RegisterMainMemory); lookups from
// the SPE threads are read-only.
class MainMemory {
 public:
  struct Region {
    uint64_t begin = 0;
    uint64_t end = 0;  // One past the last byte.
    std::string name;
  };

  // `base` must be 4-byte aligned (DMA further needs 16-byte aligned EAs); regions must not
  // overlap.
  absl::Status Register(const void* base, size_t bytes, std::string name);
  absl::Status Unregister(const void* base);
  void Clear() { regions_.clear(); }

  // The region holding [ea, ea + size), or nullptr.
  const Region* Find(uint64_t ea, size_t size) const;
  // OK when [ea, ea + size) lies inside one region; `what` names the operation in the error.
  absl::Status Check(uint64_t ea, size_t size, const char* what) const;

  const std::vector<Region>& regions() const { return regions_; }

 private:
  std::vector<Region> regions_;  // Sorted by begin.
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_MAIN_MEMORY_H_
