// Face fields (e.g. a pressure): the surviving fan faces get values that keep each group's
// resultant over the fan where they can (engine/mechanics.h, TransferFields); what cannot be
// kept is spent from the ledger, where each field's resultant per group may change by at most
// max_field_change of the group's total absolute load. On whenever the mesh carries fields.
#include "engine/rule.h"

namespace femsimp {
namespace {

class FieldResultantRule final : public CollapseRule {
 public:
  FieldResultantRule(double max_change, int fields, const GroupIndex* groups)
      : max_change_(max_change), fields_(fields), groups_(groups) {}
  Reject reason() const override { return Reject::kFieldResultant; }
  uint32_t stages() const override { return Stages(RuleStage::kFidelity, RuleStage::kBudget); }
  bool reads_face_attrs() const override { return true; }
  // TransferFields keeps the resultant over V's fan; a full-edge collapse would also reshape
  // Vd's faces, whose values it does not move. Runs with fields collapse half-edges.
  bool judges_placement() const override { return false; }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const int nf = p.fan->faces;
    int slot[kMaxRing] = {};
    for (int f = 0; f < nf; ++f) slot[f] = groups_->Of(p.fan->group[f]);
    FaceAttrQ transferred[kMaxRing];
    TransferFields(*p.fan, p.target, fields_, p.new_attr, slot, transferred, &p.delta);
    for (int f = 0; f < nf; ++f) p.new_attr[f] = transferred[f];
    p.cycles += 60 * nf * fields_;
    return Verdict::kPass;
  }

  bool WithinBudget(const LedgerView& t, const CollapseDelta& delta) const override {
    for (int i = 0; i < delta.entries; ++i) {
      const int s = delta.slot[i];
      if (Norm(t.force_spent[s] + delta.force[i]) > max_change_ * t.reference.load[s]) return false;
    }
    return true;
  }

 private:
  double max_change_;
  int fields_;
  const GroupIndex* groups_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeFieldResultantRule(const SimplifyOptions& o, const RuleSetup& s) {
  if (s.fields <= 0) return nullptr;
  return std::make_unique<FieldResultantRule>(o.max_field_change, s.fields, s.groups);
}

}  // namespace femsimp
