// The enclosed volume of a closed mesh changes by at most max_volume_change of the input's,
// summed over every collapse of the run (spent from the ledger under its lock).
#include <cmath>

#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

class VolumeBudgetRule final : public CollapseRule {
 public:
  VolumeBudgetRule(double max_change, bool closed) : max_change_(max_change), closed_(closed) {}
  Reject reason() const override { return Reject::kVolume; }
  uint32_t stages() const override {
    return static_cast<uint32_t>(RuleStage::kFidelity) | static_cast<uint32_t>(RuleStage::kBudget);
  }
  bool tracks_mass() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    MeasureMassChange(closed_, p);
    return Verdict::kPass;
  }
  bool WithinBudget(const LedgerView& t, const CollapseDelta&) const override {
    return !(std::fabs(t.spent.measure) > max_change_ * std::fabs(t.input.measure));
  }

 private:
  double max_change_;
  bool closed_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeVolumeBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_volume_change > 0.0)) return nullptr;
  return std::make_unique<VolumeBudgetRule>(o.max_volume_change, s.closed);
}

}  // namespace femsimp
