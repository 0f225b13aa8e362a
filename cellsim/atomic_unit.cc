#include "cellsim/atomic_unit.h"

#include <atomic>

#include "absl/strings/str_format.h"

namespace femsimp::cellsim {

absl::Status AtomicUnit::Check(const uint32_t* ea, const char* what) const {
  if (reinterpret_cast<uintptr_t>(ea) % alignof(uint32_t) != 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("atomic %s: word address %p is not 4-byte aligned", what, ea));
  }
  return memory_->Check(Ea(ea), sizeof(uint32_t), what);
}

absl::StatusOr<uint32_t> AtomicUnit::GetLlar(uint32_t* ea) {
  if (absl::Status s = Check(ea, "getllar"); !s.ok()) return s;
  ++counters_->atomic_getllar;
  clock_->AddAtomic(cost_->atomic_getllar_cycles);
  reserved_ = ea;
  reserved_value_ = std::atomic_ref<uint32_t>(*ea).load(std::memory_order_acquire);
  return reserved_value_;
}

absl::StatusOr<bool> AtomicUnit::PutLlc(uint32_t* ea, uint32_t value) {
  if (absl::Status s = Check(ea, "putllc"); !s.ok()) return s;
  clock_->AddAtomic(cost_->atomic_putllc_cycles);
  bool ok = false;
  if (reserved_ == ea) {
    uint32_t expected = reserved_value_;
    ok = std::atomic_ref<uint32_t>(*ea).compare_exchange_strong(
        expected, value, std::memory_order_acq_rel, std::memory_order_acquire);
  }
  reserved_ = nullptr;
  ++(ok ? counters_->atomic_putllc_success : counters_->atomic_putllc_failure);
  return ok;
}

absl::Status AtomicUnit::PutLluc(uint32_t* ea, uint32_t value) {
  if (absl::Status s = Check(ea, "putlluc"); !s.ok()) return s;
  ++counters_->atomic_putlluc;
  clock_->AddAtomic(cost_->atomic_putlluc_cycles);
  if (reserved_ == ea) reserved_ = nullptr;  // Our own write kills our reservation too.
  std::atomic_ref<uint32_t>(*ea).store(value, std::memory_order_release);
  return absl::OkStatus();
}

absl::StatusOr<uint32_t> AtomicUnit::Load(uint32_t* ea) {
  if (absl::Status s = Check(ea, "load"); !s.ok()) return s;
  ++counters_->atomic_loads;
  clock_->AddAtomic(cost_->atomic_load_cycles);
  return std::atomic_ref<uint32_t>(*ea).load(std::memory_order_acquire);
}

absl::StatusOr<bool> AtomicUnit::CompareAndSwap(uint32_t* ea, uint32_t& expected,
                                                uint32_t desired) {
  for (;;) {
    absl::StatusOr<uint32_t> seen = GetLlar(ea);
    if (!seen.ok()) return seen.status();
    if (*seen != expected) {
      reserved_ = nullptr;
      expected = *seen;
      return false;
    }
    absl::StatusOr<bool> put = PutLlc(ea, desired);
    if (!put.ok()) return put.status();
    if (*put) return true;
  }
}

}  // namespace femsimp::cellsim
