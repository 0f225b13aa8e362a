#ifndef FEMSIMP_CELLSIM_SPE_SORT_H_
#define FEMSIMP_CELLSIM_SPE_SORT_H_

#include <cstddef>
#include <cstdint>

#include "absl/status/statusor.h"
#include "cellsim/runtime.h"

namespace femsimp::cellsim {

// What one SortOnSpes did; its cycles are also in the SPEs' counters and clocks.
struct SpeSortStats {
  uint64_t keys = 0;
  uint64_t block_keys = 0;      // keys per block sorted inside one local store
  int levels = 0;               // merge levels after the block sort
  uint64_t runs = 0;            // Runtime::Run calls (block sort + one per level)
  uint64_t merged = 0;          // elements output by merge steps, all SPEs (block sort included)
  uint64_t probes = 0;          // keys read by the merge-path searches (one DMA get each)
  uint64_t elapsed_cycles = 0;  // modeled: the runs' last_run_cycles summed
};

// Sorts the n 64-bit keys at `keys` ascending on the runtime's SPEs (the paper's remedy for the
// PPE's sequential sort: each SPE sorts its share, then the shares are merged), leaving the
// result in `keys`; `scratch` holds n keys between levels.
//  1. Block sort (one run): the keys are cut into blocks of at most kMaxBlockKeys, about one
//     per SPE when that is fewer; each SPE gets its blocks by DMA into its local store, sorts
//     them there (bottom-up merge sort) and puts them back.
//  2. Merge levels (one run each): sorted runs are merged pairwise until one is left. At every
//     level SPE i writes the i-th even-aligned slice of the output whatever runs it spans, so
//     the work stays balanced when there are fewer runs than SPEs: where its slice starts
//     inside a pair of runs it finds the split by a binary search over the two runs (the merge
//     path, one DMA get per key probed). Inputs stream in through double-buffered gets, the
//     output leaves through double-buffered puts.
// Modeled time: CostModel::sort_merge_cycles per element a merge step outputs (a run without
// partner is copied at 1 cycle per key), the DMA engine's timing for every transfer, the block
// sort's launch (spe_run_overhead_cycles) and each merge level's wake-up of the resident
// program (CostModel::ResidentSyncCycles). Needs n even, both arrays 16-byte aligned and registered
// as main memory, and kSortLsBytes free in every local store. Between runs only (not inside a
// kernel); uses DMA tags 0..8.
inline constexpr size_t kMaxBlockKeys = 4096;
inline constexpr size_t kSortLsBytes = 2 * kMaxBlockKeys * sizeof(uint64_t);
absl::StatusOr<SpeSortStats> SortOnSpes(Runtime& runtime, uint64_t* keys, uint64_t* scratch,
                                        size_t n);

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_SPE_SORT_H_
