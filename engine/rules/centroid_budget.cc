// The centre of mass (of the solid, or of the surface of an open mesh) moves by at most
// max_centroid_shift of the bounding-box diagonal over the run (spent from the ledger).
#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

class CentroidBudgetRule final : public CollapseRule {
 public:
  CentroidBudgetRule(double max_shift, bool closed, double diagonal)
      : max_shift_(max_shift), closed_(closed), diagonal_(diagonal) {}
  Reject reason() const override { return Reject::kCentroid; }
  uint32_t stages() const override {
    return static_cast<uint32_t>(RuleStage::kFidelity) | static_cast<uint32_t>(RuleStage::kBudget);
  }
  bool tracks_mass() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    MeasureMassChange(closed_, p);
    return Verdict::kPass;
  }
  bool WithinBudget(const LedgerView& t, const CollapseDelta&) const override {
    const MassProperties now{t.input.measure + t.spent.measure, t.input.moment + t.spent.moment};
    return now.measure != 0.0 &&
           !(Norm(now.centroid() - t.input.centroid()) > max_shift_ * diagonal_);
  }

 private:
  double max_shift_;
  bool closed_;
  double diagonal_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeCentroidBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_centroid_shift > 0.0)) return nullptr;
  return std::make_unique<CentroidBudgetRule>(o.max_centroid_shift, s.closed, s.diagonal);
}

}  // namespace femsimp
