// Feature lines (docs/FIDELITY.md): feature edges — sharp edges, boundaries and face-group
// borders, flagged before the passes — stay where they are. A vertex with one, or three or
// more, feature edges, or whose two feature edges turn sharply, is a corner and never moves; a
// vertex with two slides only along its line, and never folds the line onto a feature edge Vd
// already has.
#include "engine/features.h"
#include "engine/rule.h"

namespace femsimp {
namespace {

class FeatureLineRule final : public CollapseRule {
 public:
  explicit FeatureLineRule(double cos_feature) : cos_feature_(cos_feature) {}
  Reject reason() const override { return Reject::kFeature; }
  uint32_t stages() const override { return Stages(RuleStage::kDirections, RuleStage::kTopology); }

  void Restrict(const Ring& fan, Directions* d) const override {
    int features = 0;
    int line[2] = {-1, -1};
    for (int i = 0; i < fan.neighbours(); ++i)
      if (fan.feature[i]) {
        if (features < 2) line[features] = i;
        ++features;
      }
    if ((features != 0 && features != 2) || (features == 0 && fan.boundary) ||
        (features == 2 &&
         TurnsSharply(fan.pos[line[0]], fan.center_pos, fan.pos[line[1]], cos_feature_))) {
      d->fixed = true;
      return;
    }
    if (features == 2) {
      d->line[0] = line[0];
      d->line[1] = line[1];
    }
  }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    if (p.line_other < 0) return Verdict::kPass;
    const uint32_t left_behind = p.fan->nbr[p.line_other];
    const Ring& other = *p.target_fan;
    for (int a = 0; a < other.neighbours(); ++a)
      if (other.nbr[a] == left_behind && other.feature[a]) return Verdict::kReject;
    return Verdict::kPass;
  }

 private:
  double cos_feature_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeFeatureLineRule(const SimplifyOptions&, const RuleSetup& s) {
  return std::make_unique<FeatureLineRule>(s.cos_feature);
}

}  // namespace femsimp
