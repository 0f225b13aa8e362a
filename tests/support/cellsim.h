#ifndef FEMSIMP_TESTS_SUPPORT_CELLSIM_H_
#define FEMSIMP_TESTS_SUPPORT_CELLSIM_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "cellsim/main_memory.h"
#include "cellsim/spe_context.h"
#include "gtest/gtest.h"

namespace femsimp::cellsim::testing {

// One 16-byte main-memory element, like a vertex or half-edge of the engine.
struct alignas(16) Quad {
  uint32_t w[4];
};

// An SPE context over `memory`, failing the test when it cannot be created.
inline std::unique_ptr<SpeContext> MakeSpe(const MainMemory& memory, SpeConfig config = {},
                                           int index = 0, int num_spes = 1) {
  absl::StatusOr<std::unique_ptr<SpeContext>> spe =
      SpeContext::Create(index, num_spes, config, &memory);
  EXPECT_TRUE(spe.ok()) << spe.status();
  return spe.ok() ? std::move(*spe) : nullptr;
}

// n quadwords starting on a 128-byte boundary (so line counts are exact); quad i holds
// {i, i + 1, i + 2, i + 3}.
class QuadArray {
 public:
  explicit QuadArray(size_t n) : storage_(n + 8), size_(n) {
    const auto p = reinterpret_cast<uintptr_t>(storage_.data());
    data_ = storage_.data() + ((128 - p % 128) % 128) / sizeof(Quad);
    for (size_t i = 0; i < n; ++i) {
      for (uint32_t j = 0; j < 4; ++j) data_[i].w[j] = static_cast<uint32_t>(i) + j;
    }
  }
  Quad& operator[](size_t i) { return data_[i]; }
  Quad* data() { return data_; }
  size_t size() const { return size_; }
  size_t bytes() const { return size_ * sizeof(Quad); }

 private:
  std::vector<Quad> storage_;
  Quad* data_;
  size_t size_;
};

}  // namespace femsimp::cellsim::testing

#endif  // FEMSIMP_TESTS_SUPPORT_CELLSIM_H_
