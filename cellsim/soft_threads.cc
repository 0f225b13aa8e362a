#include "cellsim/soft_threads.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "absl/strings/str_format.h"

#if defined(__SANITIZE_THREAD__)
#define FEMSIMP_CELLSIM_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define FEMSIMP_CELLSIM_TSAN 1
#endif
#endif

#ifdef FEMSIMP_CELLSIM_TSAN
#include <sanitizer/tsan_interface.h>
#endif

namespace femsimp::cellsim {
namespace {
constexpr size_t kCanaryBytes = 64;
constexpr unsigned char kCanary = 0xC5;
constexpr size_t kMinStackBytes = 4 * 1024;

void* CurrentTsanFiber() {
#ifdef FEMSIMP_CELLSIM_TSAN
  return __tsan_get_current_fiber();
#else
  return nullptr;
#endif
}
void* CreateTsanFiber() {
#ifdef FEMSIMP_CELLSIM_TSAN
  return __tsan_create_fiber(0);
#else
  return nullptr;
#endif
}
void DestroyTsanFiber([[maybe_unused]] void* fiber) {
#ifdef FEMSIMP_CELLSIM_TSAN
  if (fiber != nullptr) __tsan_destroy_fiber(fiber);
#endif
}
// Tells TSan the next swapcontext enters `fiber` (it then attributes accesses correctly and
// sees the switch as synchronisation within the host thread).
void SwitchTsanFiber([[maybe_unused]] void* fiber) {
#ifdef FEMSIMP_CELLSIM_TSAN
  __tsan_switch_to_fiber(fiber, 0);
#endif
}
}  // namespace

struct SoftThreadScheduler::Fiber {
  ucontext_t context;
  std::byte* stack = nullptr;  // Lowest address; the canary sits there (stacks grow down).
  uint64_t ready_at = 0;
  bool done = false;
  void* tsan_fiber = nullptr;
};

absl::Status SoftThreadScheduler::Run(int k, size_t stack_bytes, const Body& body) {
  if (k < 1) {
    return absl::InvalidArgumentError(
        absl::StrFormat("software threads: need at least 1 thread, got %d", k));
  }
  if (stack_bytes < kMinStackBytes || stack_bytes % 16 != 0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("software threads: stack size %d must be a multiple of 16 of at least %d",
                        stack_bytes, kMinStackBytes));
  }
  if (active() || body_ != nullptr) {
    return absl::FailedPreconditionError("software threads: RunThreads is already running");
  }
  const LocalStore::Marker mark = ls_->Mark();
  absl::StatusOr<std::byte*> blocks =
      ls_->Allocate(sizeof(Fiber) * k, 16, "software thread control blocks");
  if (!blocks.ok()) return blocks.status();
  Fiber* fibers = reinterpret_cast<Fiber*>(*blocks);
  std::uninitialized_default_construct_n(fibers, k);
  for (int i = 0; i < k; ++i) {
    absl::StatusOr<std::byte*> stack =
        ls_->Allocate(stack_bytes, 16, absl::StrFormat("software thread %d stack", i));
    if (!stack.ok()) {
      std::destroy_n(fibers, k);
      ls_->Release(mark);
      return stack.status();
    }
    fibers[i].stack = *stack;
  }

  body_ = &body;
  fibers_ = fibers;
  num_threads_ = k;
  stack_bytes_ = stack_bytes;
  last_ = k - 1;  // So that thread 0 runs first.
  scheduler_tsan_fiber_ = CurrentTsanFiber();
  for (int i = 0; i < k; ++i) InitFiber(fibers[i]);

  int alive = k;
  bool first = true;
  while (alive > 0) {
    const int next = PickNext();
    // A switch: the SPU leaves a live thread that is waiting for another thread.
    if (!first && next != last_ && !fibers_[last_].done) {
      ++counters_->thread_switches;
      clock_->AddSwitch(cost_->thread_switch_cycles);
    }
    first = false;
    Resume(next);
    CheckCanary(next);
    last_ = next;
    if (fibers_[next].done) {
      --alive;
      DestroyTsanFiber(fibers_[next].tsan_fiber);
      fibers_[next].tsan_fiber = nullptr;
    }
  }

  std::destroy_n(fibers, k);
  body_ = nullptr;
  fibers_ = nullptr;
  num_threads_ = 0;
  ls_->Release(mark);
  return absl::OkStatus();
}

// Its own function: getcontext returns twice in principle, and no local of Run may live across it
// (-Wclobbered).
void SoftThreadScheduler::InitFiber(Fiber& f) {
  const uintptr_t self = reinterpret_cast<uintptr_t>(this);
  std::memset(f.stack, kCanary, kCanaryBytes);
  getcontext(&f.context);
  f.context.uc_stack.ss_sp = f.stack;
  f.context.uc_stack.ss_size = stack_bytes_;
  f.context.uc_link = nullptr;
  makecontext(&f.context, reinterpret_cast<void (*)()>(&Trampoline), 2,
              static_cast<unsigned>(self & 0xffffffffu), static_cast<unsigned>(self >> 32));
  f.ready_at = clock_->Now();
  f.tsan_fiber = CreateTsanFiber();
}

int SoftThreadScheduler::PickNext() {
  const uint64_t now = clock_->Now();
  // Round robin from the thread after the last one, the last one itself checked last.
  for (int step = 1; step <= num_threads_; ++step) {
    const int i = (last_ + step) % num_threads_;
    if (!fibers_[i].done && fibers_[i].ready_at <= now) return i;
  }
  int earliest = -1;
  for (int i = 0; i < num_threads_; ++i) {
    if (fibers_[i].done) continue;
    if (earliest < 0 || fibers_[i].ready_at < fibers_[earliest].ready_at) earliest = i;
  }
  clock_->StallUntil(fibers_[earliest].ready_at);
  return earliest;
}

void SoftThreadScheduler::Resume(int index) {
  current_ = index;
  SwitchTsanFiber(fibers_[index].tsan_fiber);
  swapcontext(&scheduler_context_, &fibers_[index].context);
  current_ = -1;
}

void SoftThreadScheduler::SwitchToScheduler() {
  Fiber& f = fibers_[current_];
  SwitchTsanFiber(scheduler_tsan_fiber_);
  swapcontext(&f.context, &scheduler_context_);
}

void SoftThreadScheduler::Trampoline(unsigned lo, unsigned hi) {
  auto* self = reinterpret_cast<SoftThreadScheduler*>(uintptr_t{lo} | (uintptr_t{hi} << 32));
  const int index = self->current_;
  (*self->body_)(index);
  self->fibers_[index].done = true;
  self->SwitchToScheduler();
  std::abort();  // A finished thread is never resumed.
}

void SoftThreadScheduler::CheckCanary(int index) const {
  const std::byte* stack = fibers_[index].stack;
  for (size_t i = 0; i < kCanaryBytes; ++i) {
    if (stack[i] != std::byte{kCanary}) {
      std::fprintf(stderr,
                   "cellsim: software thread %d overflowed its %zu-byte local-store stack; "
                   "raise SpeConfig::thread_stack_bytes\n",
                   index, stack_bytes_);
      std::abort();
    }
  }
}

void SoftThreadScheduler::WaitUntil(uint64_t cycle) {
  if (cycle <= clock_->Now()) return;
  if (!active() || num_threads_ == 1) {
    clock_->StallUntil(cycle);
    return;
  }
  fibers_[current_].ready_at = cycle;
  SwitchToScheduler();
}

void SoftThreadScheduler::Yield() {
  if (!active() || num_threads_ == 1) return;
  fibers_[current_].ready_at = clock_->Now();
  SwitchToScheduler();
}

}  // namespace femsimp::cellsim
