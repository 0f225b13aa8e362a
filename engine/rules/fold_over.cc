// No new triangle may turn over against the one it replaces. Checked in every mode.
#include "engine/rule.h"

namespace femsimp {
namespace {

class FoldOverRule final : public CollapseRule {
 public:
  Reject reason() const override { return Reject::kFoldOver; }
  uint32_t stages() const override { return Stages(RuleStage::kShape); }
  uint32_t cycles_per_face() const override { return 8; }
  bool fan_local() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const CollapseGeometry& g = p.geometry;
    for (int i = 0; i < g.faces; ++i)
      if (!(Dot(g.old_normal[i], g.new_normal[i]) > 0.0)) return Verdict::kReject;
    return Verdict::kPass;
  }
};

}  // namespace

std::unique_ptr<CollapseRule> MakeFoldOverRule(const SimplifyOptions&, const RuleSetup&) {
  return std::make_unique<FoldOverRule>();
}

}  // namespace femsimp
