// The centre of mass (of the solid, or of the surface of an open mesh) moves by at most
// max_centroid_shift of the bounding-box diagonal over the run (spent from the ledger).
#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

class CentroidBudgetRule final : public MassBudgetRule {
 public:
  CentroidBudgetRule(double max_shift, const RuleSetup& s)
      : MassBudgetRule(s), max_distance_(max_shift * s.diagonal) {}
  Reject reason() const override { return Reject::kCentroid; }
  bool WithinBudget(const LedgerView& t, const CollapseDelta&) const override {
    const MassProperties now{
        t.input.measure + t.spent.measure, t.input.moment + t.spent.moment, {}};
    return now.measure != 0.0 && !(Norm(now.centroid() - t.input.centroid()) > max_distance_);
  }

 private:
  double max_distance_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeCentroidBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_centroid_shift > 0.0)) return nullptr;
  return std::make_unique<CentroidBudgetRule>(o.max_centroid_shift, s);
}

}  // namespace femsimp
