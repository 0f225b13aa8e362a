#ifndef FEMSIMP_CELLSIM_ATOMIC_UNIT_H_
#define FEMSIMP_CELLSIM_ATOMIC_UNIT_H_

#include <cstdint>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "cellsim/cost_model.h"
#include "cellsim/cycle_clock.h"
#include "cellsim/main_memory.h"

namespace femsimp::cellsim {

// The atomic unit of one SPE, for 32-bit words in main memory (the vertex status words).
// Words are plain, 4-byte aligned uint32_t inside a registered MainMemory region; every
// concurrent access must go through an AtomicUnit (or std::atomic_ref on the PPE side).
//
// Reservation style, as getllar/putllc on the Cell BE: GetLlar loads a word and reserves it;
// PutLlc stores only if the word still holds the value seen by the reservation, and drops the
// reservation either way. One reservation per SPE (a new GetLlar replaces it). The hardware
// loses the reservation on any write to the 128-byte line; the emulation compares values
// (compare-exchange), so a write of the same value (ABA) does not fail a PutLlc and writes to
// neighbouring words never do. Software threads of one SPE do not switch inside these calls.
//
// Memory order: GetLlar and Load are acquire; PutLlc (on success) and PutLluc are release.
// So an SPE that DMA-puts data and then releases a status word publishes that data to any SPE
// that acquires the word afterwards (its later DMA gets and cache fills see it, provided its
// cache lines are dirtied). Every operation is counted and charged atomic cycles.
class AtomicUnit {
 public:
  AtomicUnit(const MainMemory* memory, CycleClock* clock, SpeCounters* counters,
             const CostModel* cost)
      : memory_(memory), clock_(clock), counters_(counters), cost_(cost) {}

  // Load-and-reserve (acquire).
  absl::StatusOr<uint32_t> GetLlar(uint32_t* ea);
  // Conditional store (release): true when it succeeded, false when the reservation was lost
  // (or none was held for `ea`).
  absl::StatusOr<bool> PutLlc(uint32_t* ea, uint32_t value);
  // Unconditional atomic store (release), as putlluc.
  absl::Status PutLluc(uint32_t* ea, uint32_t value);
  // Plain atomic load (acquire), no reservation.
  absl::StatusOr<uint32_t> Load(uint32_t* ea);
  // GetLlar/PutLlc loop: if the word equals `expected`, replace it by `desired` and return
  // true; otherwise return false with `expected` set to the value seen. Retries only when the
  // reservation is lost while the word still equals `expected`.
  absl::StatusOr<bool> CompareAndSwap(uint32_t* ea, uint32_t& expected, uint32_t desired);

  bool has_reservation() const { return reserved_ != nullptr; }

 private:
  absl::Status Check(const uint32_t* ea, const char* what) const;

  const MainMemory* memory_;
  CycleClock* clock_;
  SpeCounters* counters_;
  const CostModel* cost_;
  uint32_t* reserved_ = nullptr;
  uint32_t reserved_value_ = 0;
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_ATOMIC_UNIT_H_
