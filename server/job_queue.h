// Bounded FIFO of jobs waiting for a worker. A slot is reserved when a job's spec is admitted,
// before its mesh is uploaded, so the capacity also bounds the memory of concurrent uploads.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "server/job.h"

namespace femsimp::server {

class JobQueue {
 public:
  explicit JobQueue(size_t capacity) : capacity_(capacity) {}

  // Admission: false when waiting + reserved jobs already fill the capacity, or closed.
  bool TryReserve();
  void CancelReservation();
  // Turns a reservation into a waiting job; false when the queue was closed meanwhile.
  bool PushReserved(std::shared_ptr<Job> job);
  // Blocks for the next job; nullptr once closed and empty.
  std::shared_ptr<Job> Pop();
  // Takes a waiting job out (cancelled while queued); false when a worker already has it.
  bool Remove(const Job* job);
  // Jobs ahead of this one; -1 when it is not waiting.
  int Position(const Job* job) const;
  // Stops admissions; Pop drains nothing more (the caller takes the rest with TakeAll).
  void Close();
  std::vector<std::shared_ptr<Job>> TakeAll();

  size_t waiting() const;
  size_t capacity() const { return capacity_; }

 private:
  const size_t capacity_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::shared_ptr<Job>> jobs_;
  size_t reserved_ = 0;
  bool closed_ = false;
};

}  // namespace femsimp::server
