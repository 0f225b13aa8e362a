// The link condition: V and Vd may share no neighbour but the vertices opposite their edge, so
// that the collapse joins no vertices already connected — no duplicate face, no pinched vertex,
// no change of genus.
#include "engine/rule.h"

namespace femsimp {
namespace {

class LinkConditionRule final : public CollapseRule {
 public:
  Reject reason() const override { return Reject::kLink; }
  uint32_t stages() const override { return Stages(RuleStage::kTopology); }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const Ring& fan = *p.fan;
    const Ring& other = *p.target_fan;
    for (int a = 0; a < other.neighbours(); ++a) {
      const uint32_t w = other.nbr[a];
      if (w == fan.center || w == p.opposite[0] || (p.deleted == 2 && w == p.opposite[1])) continue;
      for (int b = 0; b < fan.neighbours(); ++b)
        if (fan.nbr[b] == w) return Verdict::kReject;
    }
    return Verdict::kPass;
  }
};

}  // namespace

std::unique_ptr<CollapseRule> MakeLinkConditionRule(const SimplifyOptions&, const RuleSetup&) {
  return std::make_unique<LinkConditionRule>();
}

}  // namespace femsimp
