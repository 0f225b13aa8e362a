// The enclosed volume of a closed mesh changes by at most max_volume_change of the input's,
// summed over every collapse of the run (spent from the ledger under its lock); so does each
// part of an assembly (engine/solid_parts.h), the parts a collapse changes judged with it. An
// open mesh encloses no volume: the rule is off for it.
#include <cmath>

#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

class VolumeBudgetRule final : public MassBudgetRule {
 public:
  VolumeBudgetRule(double max_change, const RuleSetup& s) : MassBudgetRule(s), max_(max_change) {}
  Reject reason() const override { return Reject::kVolume; }
  bool WithinBudget(const LedgerView& t, const CollapseDelta&) const override {
    for (int i = 0; i < t.part_count; ++i)
      if (std::fabs(t.parts[i].spent) > max_ * std::fabs(t.parts[i].input)) return false;
    return !(std::fabs(t.spent.measure) > max_ * std::fabs(t.input.measure));
  }

 private:
  double max_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeVolumeBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_volume_change > 0.0) || !s.closed) return nullptr;
  return std::make_unique<VolumeBudgetRule>(o.max_volume_change, s);
}

}  // namespace femsimp
