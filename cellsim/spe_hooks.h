#ifndef FEMSIMP_CELLSIM_SPE_HOOKS_H_
#define FEMSIMP_CELLSIM_SPE_HOOKS_H_

#include <cstddef>
#include <cstdint>

namespace femsimp::cellsim {

// How the DMA engine and the software cache wait for a transfer to complete in model time.
// SpeContext implements it: with one software thread it stalls the clock; with several, the
// caller's thread is suspended and another ready thread runs until the cycle is reached.
class Waiter {
 public:
  virtual void WaitUntil(uint64_t cycle) = 0;

 protected:
  ~Waiter() = default;
};

// Told about every DMA put of its SPE once its data is in main memory (the software cache uses
// it to write its own puts through to lines it holds).
class PutObserver {
 public:
  virtual void OnPut(uint64_t ea, const std::byte* data, size_t size) = 0;

 protected:
  ~PutObserver() = default;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_SPE_HOOKS_H_
