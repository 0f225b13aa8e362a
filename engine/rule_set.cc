// The rules of a run, built from the options (engine/rules/rule_list.inc), and the geometry the
// shape rules judge.
#include <bit>
#include <cmath>

#include "engine/rule.h"

namespace femsimp {

#define FEMSIMP_RULE(reason, name, type) \
  std::unique_ptr<CollapseRule> Make##type(const SimplifyOptions&, const RuleSetup&);
#include "engine/rules/rule_list.inc"
#undef FEMSIMP_RULE

namespace {

constexpr RuleStage kStages[] = {RuleStage::kDirections, RuleStage::kShape,    RuleStage::kScreen,
                                 RuleStage::kTopology,   RuleStage::kFidelity, RuleStage::kBudget};

}  // namespace

int RuleSet::StageIndex(RuleStage s) { return std::countr_zero(static_cast<uint32_t>(s)); }

static_assert(static_cast<int>(Reject::kCount) <= 32, "RuleSet::fan_local_ has a bit per reason");

RuleSet RuleSet::Build(const SimplifyOptions& options, const RuleSetup& setup) {
  RuleSet set;
#define FEMSIMP_RULE(reason, name, type)                                                \
  if (std::unique_ptr<CollapseRule> rule = Make##type(options, setup); rule != nullptr) \
    set.rules_.push_back(std::move(rule));
#include "engine/rules/rule_list.inc"
#undef FEMSIMP_RULE
  for (const std::unique_ptr<CollapseRule>& rule : set.rules_) {
    for (RuleStage s : kStages)
      if (rule->in(s)) set.by_stage_[StageIndex(s)].push_back(rule.get());
    if (rule->in(RuleStage::kShape)) set.shape_cycles_ += rule->cycles_per_face();
    set.reads_face_attrs_ |= rule->reads_face_attrs();
    set.tracks_mass_ |= rule->tracks_mass();
    set.judges_placement_ &= rule->judges_placement();
    set.holds_placed_lines_ |= rule->holds_placed_lines();
    if (rule->fan_local()) set.fan_local_ |= uint32_t{1} << static_cast<int>(rule->reason());
    if (rule->placement_may_pass())
      set.placement_may_pass_ |= uint32_t{1} << static_cast<int>(rule->reason());
    if (rule->keeps_state()) set.stateful_.push_back(rule.get());
  }
  if (!set.stage(RuleStage::kBudget).empty())
    set.ledger_ = std::make_unique<MechanicsLedger>(
        *setup.mass, *setup.resultants,
        setup.sides != nullptr ? *setup.sides : std::vector<FaceSides>{},
        setup.part_volumes != nullptr ? *setup.part_volumes : std::vector<double>{});
  return set;
}

Verdict RuleSet::Check(RuleStage s, CollapseProposal& p, Reject* refused) const {
  for (const CollapseRule* rule : stage(s)) {
    const Verdict v = rule->Check(s, p);
    if (v == Verdict::kReject) *refused = rule->reason();
    if (v != Verdict::kPass) return v;
  }
  return Verdict::kPass;
}

bool RuleSet::WithinBudgets(const LedgerView& totals, const CollapseDelta& judged,
                            Reject* refused) const {
  for (const CollapseRule* rule : stage(RuleStage::kBudget))
    if (!rule->WithinBudget(totals, judged)) {
      *refused = rule->reason();
      return false;
    }
  return true;
}

bool RuleSet::SpendBudgets(uint32_t v, const CollapseDelta& delta, Reject* refused) const {
  const std::vector<const CollapseRule*>& budget = stage(RuleStage::kBudget);
  if (budget.empty() || (delta.entries == 0 && !tracks_mass_)) return true;
  const double scale = ledger_->round_scale();
  const CollapseDelta judged = scale == 1.0 ? delta : Scaled(delta, scale);
  return ledger_->TryCommit(v, delta, judged, [&](const LedgerView& totals) {
    return WithinBudgets(totals, judged, refused);
  });
}

bool RuleSet::SpendBudgetsTogether(std::span<const CollapseDelta> deltas, Reject* refused) const {
  const std::vector<const CollapseRule*>& budget = stage(RuleStage::kBudget);
  bool any_entries = false;
  for (const CollapseDelta& d : deltas) any_entries = any_entries || d.entries != 0;
  if (budget.empty() || (!any_entries && !tracks_mass_)) return true;
  std::vector<CollapseDelta> judged;
  judged.reserve(deltas.size());
  for (const CollapseDelta& d : deltas) judged.push_back(Scaled(d, double(deltas.size())));
  return ledger_->TryCommitTogether(deltas, judged, [&](const LedgerView& totals, size_t k) {
    return WithinBudgets(totals, judged[k], refused);
  });
}

void CollapseGeometry::Build(const Ring& ring, int target_index) {
  const uint32_t vd_index = ring.nbr[target_index];
  const DVec3 v = ToD(ring.center_pos);
  vd = ToD(ring.pos[target_index]);
  const int n = ring.neighbours();
  faces = 0;
  min_normal_cosine_ = 2.0;
  for (int i = 0; i < ring.faces; ++i) {
    const int j = (i + 1) % n;
    if (ring.nbr[i] == vd_index || ring.nbr[j] == vd_index) continue;  // collapsed away
    b[faces] = ToD(ring.pos[i]);
    c[faces] = ToD(ring.pos[j]);
    old_normal[faces] = Cross(b[faces] - v, c[faces] - v);
    new_normal[faces] = Cross(b[faces] - vd, c[faces] - vd);
    ++faces;
  }
  fan_faces = faces;
}

void CollapseGeometry::Build(const EdgeStar& star, DVec3* apex) {
  vd = star.p;
  old_apex = apex;
  faces = 0;
  fan_faces = 0;
  min_normal_cosine_ = 2.0;
  for (int k = 0; k < star.count; ++k) {
    if (!star.survives[k]) continue;
    if (k < star.fan_faces) ++fan_faces;
    b[faces] = star.b[k];
    c[faces] = star.c[k];
    apex[faces] = star.a[k];
    old_normal[faces] = Cross(b[faces] - star.a[k], c[faces] - star.a[k]);
    new_normal[faces] = Cross(b[faces] - vd, c[faces] - vd);
    ++faces;
  }
}

double CollapseGeometry::MinNormalCosine() const {
  if (min_normal_cosine_ <= 1.0) return min_normal_cosine_;
  double worst = 1.0;
  for (int i = 0; i < faces; ++i) {
    const double d = Dot(old_normal[i], new_normal[i]);
    const double nn = Dot(old_normal[i], old_normal[i]) * Dot(new_normal[i], new_normal[i]);
    const double c = nn > 0.0 ? d / std::sqrt(nn) : -1.0;
    worst = std::min(worst, c);
  }
  return min_normal_cosine_ = worst;
}

}  // namespace femsimp
