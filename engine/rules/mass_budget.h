// What the volume and centroid budget rules share: both spend from the ledger's mass totals,
// and the collapse's mass change is measured once for both, in the fidelity stage.
#pragma once

#include "engine/rule.h"

namespace femsimp {

class MassBudgetRule : public CollapseRule {
 public:
  explicit MassBudgetRule(const RuleSetup& s)
      : closed_(s.closed), sides_(s.sides != nullptr ? *s.sides : kNoSides) {}
  uint32_t stages() const override { return Stages(RuleStage::kFidelity, RuleStage::kBudget); }
  bool tracks_mass() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    if (!p.mass_measured) {
      if (p.star != nullptr) {
        StarMassDelta(*p.star, closed_, weight(*p.fan), p.fan->sides, &p.delta);
        p.cycles += 40 * p.star->count;
      } else {
        CollapseMassDelta(*p.fan, p.target, closed_, weight(*p.fan), &p.delta);
        p.cycles += 40 * p.fan->faces;
      }
      p.mass_measured = true;
    }
    return Verdict::kPass;
  }

 protected:
  bool closed() const { return closed_; }
  double weight(const Ring& fan) const { return FanWeight(sides_, fan); }

 private:
  static inline const std::vector<FaceSides> kNoSides;
  bool closed_;  // the solid's mass properties rather than the surface's
  const std::vector<FaceSides>& sides_;
};

}  // namespace femsimp
