// Memory admission by a job's declared mesh size (issue 15): a job's peak memory is estimated
// from the vertex and face counts its spec declares (the reader refuses chunks beyond them), and
// a job is admitted only while the estimates of the admitted jobs stay within the budget
// (--memory_budget_mib). The estimate is held from admission, before the upload, until the call
// ends (upload, queue, run and the result's stream all hold the mesh).
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>

#include "engine/simplify.h"

namespace femsimp::server {

// Peak bytes one job may take over the server's idle footprint. Measured on femsimp-server (one
// worker, one thread, the default fe preset) with /usr/bin/time -f %M over an idle server's
// 17 MB (docs/BENCHMARKS.md, "Memory per job"): 190-270 bytes per face of a closed mesh with
// its ~F/2 vertices (femur subdivided: 33.6 MB for 125 k faces, 130 MB for 499 k; blade: 45 MB
// for 260 k, 203 MB for 1.04 M), ~38 bytes more per vertex of an unwelded soup (3 per face,
// welded by the repair). The factors bound every one of those by 13 % or more; the cell back
// end adds its local stores and, per vertex, the SPE sort's key and scratch (8 bytes each), the
// rank it is made from and the free schedule's region (4 each). Face groups and fields (a few
// bytes per face each) are not counted.
inline constexpr uint64_t kJobBaseBytes = uint64_t{4} << 20;
inline constexpr uint64_t kBytesPerVertex = 64;
inline constexpr uint64_t kBytesPerFace = 256;
inline constexpr uint64_t kCellBytesPerVertex = 24;
// The wall rule's set-up (max_wall_share > 0, engine/wall_thickness.h) holds a copy of every
// face's corners (80 bytes), its hierarchy's nodes (about one per two faces, 56 bytes each) and
// a thickness per face: 112 bytes per face by its sizes (measured: knob_fine's peak grew by 52
// per face, the hierarchy freed before the run's own peak).
inline constexpr uint64_t kWallBytesPerFace = 112;
// The measured deviation check (deviation_check = measured, engine/coverage.h) keeps the input's
// triangles, their pieces per face, its grid and its feature lines' pieces for the whole run:
// measured over the same job with the mapped bound, 290-360 bytes per face at one thread, up to
// 510 with vertices placed and the mass budgets (their cut pieces); every job measured stays at
// least 20 % under its estimate (docs/BENCHMARKS.md, "Memory per job").
inline constexpr uint64_t kMeasuredBytesPerFace = 576;
// The imprint (repair's `imprint`): the mesh as it was (kept until the result is checked) and the
// contacts' constrained triangulations (CGAL's vertices, faces and constraint hierarchy, with
// the points where edges cross). Measured by the CLI's peak resident memory beside the same run
// without it: +343 bytes per face on two blocks on a plate (303 k faces, a third of them in the
// contacts), +13 on three stacked plates (408 k faces, two thirds in the contacts, whose
// triangulations are freed before the run's own peak).
inline constexpr uint64_t kImprintBytesPerFace = 512;
// The union of overlapping bodies (repair's `unite_overlaps`): the mesh as it was and the bodies'
// CGAL surfaces with exact points (the union's among them). Measured by the CLI's peak resident
// memory beside the same run without it: +355 bytes per face on two copies of knob_fine crossing
// each other (281 k faces), +394 on a sphere sunk into a box (245 k faces).
inline constexpr uint64_t kUnionBytesPerFace = 512;
uint64_t EstimateJobBytes(uint64_t vertices, uint64_t faces, const SimplifyOptions& options);

// The memory this process may use: the smaller of the physical memory and the cgroup's limit
// (a container's); 0 when neither can be read.
uint64_t AvailableMemoryBytes();

class MemoryBudget {
 public:
  // on_change(admitted bytes) runs under the lock after every change (the metrics' gauge).
  explicit MemoryBudget(
      uint64_t budget_bytes, std::function<void(uint64_t)> on_change = [](uint64_t) {});

  // Holds an admitted estimate; gives it back when destroyed.
  class Lease {
   public:
    Lease(Lease&& other) noexcept : budget_(other.budget_), bytes_(other.bytes_) {
      other.budget_ = nullptr;
    }
    Lease& operator=(Lease&&) = delete;
    ~Lease();
    uint64_t bytes() const { return bytes_; }

   private:
    friend class MemoryBudget;
    Lease(MemoryBudget* budget, uint64_t bytes) : budget_(budget), bytes_(bytes) {}
    MemoryBudget* budget_;
    uint64_t bytes_;
  };

  // A lease of `bytes` when they fit beside what is admitted, else nullopt.
  std::optional<Lease> TryAdmit(uint64_t bytes);
  uint64_t budget() const { return budget_; }
  uint64_t admitted() const;
  size_t leases() const;

 private:
  void Release(uint64_t bytes);

  const uint64_t budget_;
  const std::function<void(uint64_t)> on_change_;
  mutable std::mutex mu_;
  uint64_t admitted_ = 0;
  size_t leases_ = 0;
};

}  // namespace femsimp::server
