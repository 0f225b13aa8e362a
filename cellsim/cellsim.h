#ifndef FEMSIMP_CELLSIM_CELLSIM_H_
#define FEMSIMP_CELLSIM_CELLSIM_H_

// Umbrella header of the emulated Cell BE (see docs/CELLSIM.md).
#include "cellsim/atomic_unit.h"
#include "cellsim/cost_model.h"
#include "cellsim/counters.h"
#include "cellsim/dma_engine.h"
#include "cellsim/local_store.h"
#include "cellsim/main_memory.h"
#include "cellsim/runtime.h"
#include "cellsim/software_cache.h"
#include "cellsim/spe_context.h"
#include "cellsim/work_plan.h"

#endif  // FEMSIMP_CELLSIM_CELLSIM_H_
