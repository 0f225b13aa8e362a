// The principal moments of inertia (unit density; of the solid, or of the surface of an open
// mesh) each stay within max_inertia_change of their input values over the run, spent from the
// ledger (docs/FIDELITY.md § 5).
//
// The ledger holds the run's change of the second moment about the input's centroid (dJ) and of
// the first moment (dm about that centroid). The inertia tensor about the current centroid then
// differs from the input's by InertiaOf(dJ) - InertiaOf(dm dm^T / M), whose spectral norm is at
// most |InertiaOf(dJ)| + |dm|^2 / M; by Weyl's inequality no principal moment moves by more.
// Keeping that below F times the smallest input moment keeps every moment within F. The bound
// is convex in the totals (a norm plus a quadratic over a positive measure), as the
// deterministic rounds need (engine/rounds.h).
#include <algorithm>
#include <cmath>

#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

class InertiaBudgetRule final : public MassBudgetRule {
 public:
  InertiaBudgetRule(double max_change, const RuleSetup& s)
      : MassBudgetRule(s.closed), origin_(s.mass_origin) {
    const MassSummary input = Summarize(*s.mass, s.closed, s.mass_origin);
    allowed_ = max_change * std::min({std::fabs(input.principal_moments[0]),
                                      std::fabs(input.principal_moments[1]),
                                      std::fabs(input.principal_moments[2])});
  }
  Reject reason() const override { return Reject::kInertia; }
  Verdict Check(RuleStage stage, CollapseProposal& p) const override {
    MassBudgetRule::Check(stage, p);
    if (p.star != nullptr) {
      StarSecondMomentDelta(*p.star, closed(), origin_, &p.delta);
      p.cycles += 60 * p.star->count;
    } else {
      CollapseSecondMomentDelta(*p.fan, p.target, closed(), origin_, &p.delta);
      p.cycles += 60 * p.fan->faces;
    }
    return Verdict::kPass;
  }
  bool WithinBudget(const LedgerView& t, const CollapseDelta&) const override {
    const double measure = t.input.measure + t.spent.measure;
    if (!(measure * t.input.measure > 0.0)) return false;
    const DVec3 first = t.spent.moment - t.spent.measure * origin_;
    const double bound =
        SpectralNorm(InertiaOf(t.spent.second)) + Dot(first, first) / std::fabs(measure);
    return !(bound > allowed_);
  }

 private:
  DVec3 origin_;  // the input's centroid, where the ledger's second moments are taken
  double allowed_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeInertiaBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_inertia_change > 0.0)) return nullptr;
  return std::make_unique<InertiaBudgetRule>(o.max_inertia_change, s);
}

}  // namespace femsimp
