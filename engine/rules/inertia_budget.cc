// The principal moments of inertia (unit density; of the solid, or of the surface of an open
// mesh) each stay within max_inertia_change of their input values over the run, spent from the
// ledger (docs/FIDELITY.md § 5).
//
// The ledger holds the run's change of the second moment about the input's centroid (dJ) and of
// the first moment (dm about that centroid). The inertia tensor about the current centroid then
// differs from the input's, I0, by E = InertiaOf(dJ) - InertiaOf(dm dm^T) / M. Written in I0's
// principal frame with each axis scaled by 1 / sqrt(its moment), E becomes S, and I0 + E =
// D^1/2 (1 + S) D^1/2 for D the moments: by Ostrowski's theorem each moment, rank by rank, is
// its input value times a factor within [1 - |S|, 1 + |S|]. So |S| <= F keeps every moment
// within F of its own value, the smallest and the largest alike. The bound used,
// |S(InertiaOf(dJ))| + |dm|^2 / (M * smallest moment), is convex in the totals (a norm of a
// linear map plus a quadratic over a positive measure), as the deterministic rounds need
// (engine/rounds.h).
#include <algorithm>
#include <cmath>

#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

DVec3 Times(const Sym3& m, const DVec3& v) {
  return {m.xx * v.x + m.xy * v.y + m.zx * v.z, m.xy * v.x + m.yy * v.y + m.yz * v.z,
          m.zx * v.x + m.yz * v.y + m.zz * v.z};
}

class InertiaBudgetRule final : public MassBudgetRule {
 public:
  InertiaBudgetRule(double max_change, const RuleSetup& s)
      : MassBudgetRule(s), origin_(s.mass_origin), allowed_(max_change) {
    const MassSummary input = Summarize(*s.mass, s.closed, s.mass_origin);
    // Ascending. A moment of 0 (a part flat as a sheet of no thickness) leaves no room: nothing
    // passes (WithinBudget).
    smallest_ = input.principal_moments[0];
    if (smallest_ > 0.0)
      for (int i = 0; i < 3; ++i)
        scaled_axes_[i] = (1.0 / std::sqrt(input.principal_moments[i])) * input.principal_axes[i];
  }
  Reject reason() const override { return Reject::kInertia; }
  Verdict Check(RuleStage stage, CollapseProposal& p) const override {
    MassBudgetRule::Check(stage, p);
    if (p.star != nullptr) {
      StarSecondMomentDelta(*p.star, closed(), weight(*p.fan), origin_, &p.delta);
      p.cycles += 60 * p.star->count;
    } else {
      CollapseSecondMomentDelta(*p.fan, p.target, closed(), weight(*p.fan), origin_, &p.delta);
      p.cycles += 60 * p.fan->faces;
    }
    return Verdict::kPass;
  }
  bool WithinBudget(const LedgerView& t, const CollapseDelta&) const override {
    const double measure = t.input.measure + t.spent.measure;
    if (!(measure * t.input.measure > 0.0) || !(smallest_ > 0.0)) return false;
    const DVec3 first = t.spent.moment - t.spent.measure * origin_;
    const double bound = SpectralNorm(Scaled(InertiaOf(t.spent.second))) +
                         Dot(first, first) / (std::fabs(measure) * smallest_);
    return !(bound > allowed_);
  }

 private:
  // e in the input's principal frame, each axis scaled by 1 / sqrt(its moment).
  Sym3 Scaled(const Sym3& e) const {
    const DVec3 ea[3] = {Times(e, scaled_axes_[0]), Times(e, scaled_axes_[1]),
                         Times(e, scaled_axes_[2])};
    return Sym3{Dot(scaled_axes_[0], ea[0]), Dot(scaled_axes_[1], ea[1]),
                Dot(scaled_axes_[2], ea[2]), Dot(scaled_axes_[0], ea[1]),
                Dot(scaled_axes_[1], ea[2]), Dot(scaled_axes_[2], ea[0])};
  }

  DVec3 origin_;  // the input's centroid, where the ledger's second moments are taken
  double allowed_;
  double smallest_ = 0.0;  // the input's smallest principal moment
  DVec3 scaled_axes_[3];   // the input's principal axes over sqrt(their moments)
};

}  // namespace

std::unique_ptr<CollapseRule> MakeInertiaBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_inertia_change > 0.0)) return nullptr;
  return std::make_unique<InertiaBudgetRule>(o.max_inertia_change, s);
}

}  // namespace femsimp
