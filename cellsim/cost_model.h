#ifndef FEMSIMP_CELLSIM_COST_MODEL_H_
#define FEMSIMP_CELLSIM_COST_MODEL_H_

#include <cstddef>
#include <cstdint>

namespace femsimp::cellsim {

// Cycle costs of the emulated SPE, in SPU clock cycles (3.2 GHz on a QS21). The defaults are
// round figures in the range published for the Cell BE; they are assumptions, not measurements,
// and every one can be changed per run. docs/CELLSIM.md explains each one.
struct CostModel {
  // DMA: a transfer of B bytes issued at cycle t on an idle channel completes at
  //   t + dma_latency_cycles + ceil(B / dma_bytes_per_cycle).
  // Gets and puts each have one channel; transfers in one direction share its bandwidth
  // (the byte time is serialised, the latency overlaps).
  uint64_t dma_latency_cycles = 450;
  uint64_t dma_bytes_per_cycle = 8;  // 25.6 GB/s at 3.2 GHz, one EIB port.
  uint64_t dma_issue_cycles = 10;    // SPU channel writes to enqueue one MFC command.
  // Main memory is shared: each chip of spes_per_chip SPEs has one XDR interface (25.6 GB/s at
  // 3.2 GHz; a QS21 blade has two chips, 16 SPEs), and a run cannot end before all the bytes
  // its SPEs moved by DMA have crossed its chips' interfaces (pages interleaved over them).
  uint64_t memory_bytes_per_cycle = 8;  // per chip
  int spes_per_chip = 8;

  // Software cache bookkeeping on the SPU (tag lookup, LRU update, victim choice).
  uint64_t cache_hit_cycles = 12;
  uint64_t cache_miss_cycles = 40;  // Plus the DMA get of the line and any stall on it.

  // Atomic unit (getllar / putllc / putlluc through the MFC's atomic cache).
  uint64_t atomic_getllar_cycles = 400;
  uint64_t atomic_putllc_cycles = 100;
  uint64_t atomic_putlluc_cycles = 100;
  uint64_t atomic_load_cycles = 400;

  // One step of a merge on the SPU (cellsim/spe_sort.h): compare two 64-bit keys (no native
  // 64-bit compare: a few word compares), select, store; the same figure as the PPE's
  // comparison-and-move that the engine charges for its sequential sort.
  uint64_t sort_merge_cycles = 8;

  // Saving and restoring the SPU registers of one software-managed thread.
  uint64_t thread_switch_cycles = 50;

  // PPE cost of starting and joining the SPE contexts for one launched Runtime::Run (per run,
  // not per SPE: contexts start in parallel; a resident run costs ResidentSyncCycles instead).
  // The paper blames this for the poor fandisk speedup.
  uint64_t spe_run_overhead_cycles = 30000;

  // A resident SPE program (Runtime::Run with RunStart::kResident) is not started again: it
  // waits for the PPE's word. The PPE writes SPE 0's inbound mailbox, the SPEs pass the word on
  // along a binary tree of signal-notification writes (one DMA per level), and their reports
  // come back up the same tree to SPE 0, whose outbound mailbox the PPE reads.
  uint64_t mailbox_cycles = 500;  // one PPE <-> SPE mailbox message over MMIO, either way

  // One visit of an SPE to a shared work index (WorkPlan::Shared, Guided): a getllar + putllc.
  uint64_t IndexVisitCycles() const { return atomic_getllar_cycles + atomic_putllc_cycles; }

  // SPEs that go on from one piece of work to the next without the PPE's word: each updates a
  // word in main memory (getllar + putllc, in parallel) and the PPE reads it (one more).
  uint64_t HandOffCycles() const { return 2 * IndexVisitCycles(); }

  // What a resident run's start and end cost on n SPEs.
  uint64_t ResidentSyncCycles(int n) const {
    uint64_t levels = 0;
    while ((int64_t{1} << levels) < n) ++levels;
    return 2 * mailbox_cycles + 2 * levels * (dma_latency_cycles + dma_issue_cycles);
  }

  // Modeled duration of moving `bytes` through main memory, all n SPEs together.
  uint64_t MemoryCycles(uint64_t bytes, int n) const {
    const uint64_t per_chip = spes_per_chip < 1 ? 1 : uint64_t(spes_per_chip);
    const uint64_t chips = (uint64_t(n < 1 ? 1 : n) + per_chip - 1) / per_chip;
    const uint64_t bpc = (memory_bytes_per_cycle == 0 ? 1 : memory_bytes_per_cycle) * chips;
    return (bytes + bpc - 1) / bpc;
  }

  // Modeled duration of moving `bytes` over one channel (without latency).
  uint64_t ByteCycles(size_t bytes) const {
    const uint64_t bpc = dma_bytes_per_cycle == 0 ? 1 : dma_bytes_per_cycle;
    return (bytes + bpc - 1) / bpc;
  }
};

}  // namespace femsimp::cellsim

#endif  // FEMSIMP_CELLSIM_COST_MODEL_H_
