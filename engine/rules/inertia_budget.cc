// The principal moments of inertia (unit density; of the solid, or of the surface of an open
// mesh) each stay within max_inertia_change F of their input values over the run, spent from the
// ledger (docs/FIDELITY.md § 5).
//
// The ledger holds the run's change of the second moment about the input's centroid (dJ) and of
// the first moment (dm about that centroid). The inertia tensor about the current centroid is
// then I = I0 + L(dJ) - L(dm dm^T) / M, L(J) = tr(J) 1 - J. In I0's principal frame, moments
// d0 <= d1 <= d2, Cauchy's interlacing bounds the k-th moment of I between the smallest
// eigenvalue of I's block on axes k..2 and the largest of its block on axes 0..k. The last term
// only lowers I (positive semi-definite), so the upper test leaves it out and stays linear in the
// totals; the lower test keeps it, and is concave in them (each x^T L(dm dm^T) x / M is a
// quadratic over a positive linear function). Both sets of allowed totals are convex, as the
// deterministic rounds need (engine/rounds.h). A change that turns the principal axes enters
// only to second order, where a bound on the whole change, |D^-1/2 E D^-1/2| (Ostrowski, until
// session 63), took it to first order and refused slender parts' turns.
#include <algorithm>
#include <cmath>

#include "engine/rules/mass_budget.h"

namespace femsimp {
namespace {

DVec3 Times(const Sym3& m, const DVec3& v) {
  return {m.xx * v.x + m.xy * v.y + m.zx * v.z, m.xy * v.x + m.yy * v.y + m.yz * v.z,
          m.zx * v.x + m.yz * v.y + m.zz * v.z};
}

// The largest and the smallest eigenvalue of the 2x2 block [[a, b], [b, c]].
double LargestOf2(double a, double c, double b) {
  return 0.5 * (a + c) + std::hypot(0.5 * (a - c), b);
}
double SmallestOf2(double a, double c, double b) {
  return 0.5 * (a + c) - std::hypot(0.5 * (a - c), b);
}

class InertiaBudgetRule final : public MassBudgetRule {
 public:
  InertiaBudgetRule(double max_change, const RuleSetup& s)
      : MassBudgetRule(s), origin_(s.mass_origin), allowed_(max_change) {
    const MassSummary input = Summarize(*s.mass, s.closed, s.mass_origin);
    for (int i = 0; i < 3; ++i) {
      moments_[i] = input.principal_moments[i];  // ascending
      axes_[i] = input.principal_axes[i];
    }
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
    // A moment of 0 (a part flat as a sheet of no thickness) leaves no room.
    const double measure = t.input.measure + t.spent.measure;
    if (!(measure > 0.0) || !(t.input.measure > 0.0) || !(moments_[0] > 0.0)) return false;
    const DVec3 first = t.spent.moment - t.spent.measure * origin_;
    Sym3 upper = InPrincipalFrame(InertiaOf(t.spent.second));
    upper.xx += moments_[0];
    upper.yy += moments_[1];
    upper.zz += moments_[2];
    const Sym3 lower = upper - (1.0 / measure) * InPrincipalFrame(InertiaOf(Outer(first)));
    const double up = 1.0 + allowed_, down = 1.0 - allowed_;
    return upper.xx <= up * moments_[0] &&
           LargestOf2(upper.xx, upper.yy, upper.xy) <= up * moments_[1] &&
           Eigen(upper).values[2] <= up * moments_[2] &&
           Eigen(lower).values[0] >= down * moments_[0] &&
           SmallestOf2(lower.yy, lower.zz, lower.yz) >= down * moments_[1] &&
           lower.zz >= down * moments_[2];
  }

 private:
  // e in the input's principal frame: xx on the smallest moment's axis, zz on the largest's.
  Sym3 InPrincipalFrame(const Sym3& e) const {
    const DVec3 ea[3] = {Times(e, axes_[0]), Times(e, axes_[1]), Times(e, axes_[2])};
    return Sym3{Dot(axes_[0], ea[0]), Dot(axes_[1], ea[1]), Dot(axes_[2], ea[2]),
                Dot(axes_[0], ea[1]), Dot(axes_[1], ea[2]), Dot(axes_[2], ea[0])};
  }

  DVec3 origin_;  // the input's centroid, where the ledger's second moments are taken
  double allowed_;
  double moments_[3];  // the input's principal moments, ascending
  DVec3 axes_[3];      // and their unit axes
};

}  // namespace

std::unique_ptr<CollapseRule> MakeInertiaBudgetRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (!(o.max_inertia_change > 0.0)) return nullptr;
  return std::make_unique<InertiaBudgetRule>(o.max_inertia_change, s);
}

}  // namespace femsimp
