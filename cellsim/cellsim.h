#ifndef FEMSIMP_CELLSIM_CELLSIM_H_
#define FEMSIMP_CELLSIM_CELLSIM_H_

// Umbrella header of the emulated Cell BE (see docs/CELLSIM.md).
//
// Typical use by a back end (error handling shortened):
//
//   auto rt = *Runtime::Create({.num_spes = 8});
//   rt->RegisterMainMemory(quads.data(), quads.size() * 16, "half-edges");
//   rt->RegisterMainMemory(status.data(), status.size() * 4, "status");
//   rt->Run([&](SpeContext& spe) {
//     spe.RunThreads(K, [&](SpeContext& ctx, int) {
//       while (std::optional<uint64_t> v = ctx.NextWorkItem()) {
//         uint32_t expected = kRemovable;                        // Lock the vertex.
//         if (!*ctx.atomic().CompareAndSwap(&status[*v], expected, kLocked)) {
//           ++ctx.counters().lock_conflicts;
//           continue;
//         }
//         Quad q = *ctx.cache().ReadValue<Quad>(Ea(&quads[*v]));  // May yield on a miss.
//         ctx.AddComputeCycles(200);
//         alignas(16) Quad out = Modify(q);                     // On the LS stack.
//         ctx.dma().Put(&out, Ea(&quads[*v]), 16, /*tag=*/0);
//         ctx.dma().WaitTagMask(1u << 0);
//         ctx.atomic().PutLluc(&status[*v], kRemoved);          // Release.
//       }
//     });
//   }, WorkPlan::PerSpe(candidate_lists));
#include "cellsim/atomic_unit.h"
#include "cellsim/cost_model.h"
#include "cellsim/counters.h"
#include "cellsim/dma_engine.h"
#include "cellsim/local_store.h"
#include "cellsim/main_memory.h"
#include "cellsim/runtime.h"
#include "cellsim/software_cache.h"
#include "cellsim/spe_context.h"
#include "cellsim/spe_sort.h"
#include "cellsim/work_plan.h"

#endif  // FEMSIMP_CELLSIM_CELLSIM_H_
