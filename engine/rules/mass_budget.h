// Shared by the volume and centroid budget rules: the collapse's mass change, measured once.
#pragma once

#include "engine/rule.h"

namespace femsimp {

inline void MeasureMassChange(bool closed, CollapseProposal& p) {
  if (p.mass_measured) return;
  CollapseMassDelta(*p.fan, p.target, closed, &p.delta);
  p.cycles += 40 * p.fan->faces;
  p.mass_measured = true;
}

}  // namespace femsimp
