#include "server/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <string>

namespace femsimp::server {
namespace {

// The first number in `path` ("max", a missing file or garbage: 0, no limit).
uint64_t ReadLimit(const char* path) {
  std::ifstream in(path);
  uint64_t v = 0;
  if (!(in >> v)) return 0;
  return v;
}

}  // namespace

uint64_t EstimateJobBytes(uint64_t vertices, uint64_t faces, const SimplifyOptions& options) {
  uint64_t bytes = kJobBaseBytes + kBytesPerVertex * vertices + kBytesPerFace * faces;
  if (options.backend == Backend::kCell)
    bytes += uint64_t(options.cell.spes) * uint64_t(options.cell.local_store_kib) * 1024 +
             kCellBytesPerVertex * vertices;
  if (options.max_wall_share > 0.0) bytes += kWallBytesPerFace * faces;
  if (options.deviation_check == DeviationCheck::kMeasured) bytes += kMeasuredBytesPerFace * faces;
  if (options.repair.imprint) bytes += kImprintBytesPerFace * faces;
  if (options.repair.unite_overlaps) bytes += kUnionBytesPerFace * faces;
  return bytes;
}

uint64_t AvailableMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  uint64_t bytes = pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : 0;
  // cgroup v2, then v1 (whose "no limit" is a huge number, above the physical memory).
  for (const char* path :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const uint64_t limit = ReadLimit(path);
    if (limit > 0) bytes = bytes == 0 ? limit : std::min(bytes, limit);
  }
  return bytes;
}

MemoryBudget::MemoryBudget(uint64_t budget_bytes, std::function<void(uint64_t)> on_change)
    : budget_(budget_bytes), on_change_(std::move(on_change)) {
  on_change_(0);
}

MemoryBudget::Lease::~Lease() {
  if (budget_ != nullptr) budget_->Release(bytes_);
}

std::optional<MemoryBudget::Lease> MemoryBudget::TryAdmit(uint64_t bytes) {
  std::lock_guard<std::mutex> lock(mu_);
  if (bytes > budget_ - std::min(admitted_, budget_)) return std::nullopt;
  admitted_ += bytes;
  ++leases_;
  on_change_(admitted_);
  return Lease(this, bytes);
}

void MemoryBudget::Release(uint64_t bytes) {
  std::lock_guard<std::mutex> lock(mu_);
  admitted_ -= bytes;
  --leases_;
  on_change_(admitted_);
}

uint64_t MemoryBudget::admitted() const {
  std::lock_guard<std::mutex> lock(mu_);
  return admitted_;
}

size_t MemoryBudget::leases() const {
  std::lock_guard<std::mutex> lock(mu_);
  return leases_;
}

}  // namespace femsimp::server
