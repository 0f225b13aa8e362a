// The FE check's options as command-line flags (femsimp check, femsimp simplify --fe-check),
// with the ranges of fe_check.h.
#pragma once

#include "common/flags.h"
#include "fecheck/fe_check.h"

namespace femsimp::fecheck {

// --youngs-modulus, --poisson-ratio, --density, --unit-scale, --modes, --fe-threads.
void AddFeCheckFlags(flags::FlagSet& set, FeCheckOptions* options);

}  // namespace femsimp::fecheck
