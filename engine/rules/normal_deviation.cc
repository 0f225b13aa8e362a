// Each new triangle's normal within max_normal_deviation_deg of the normal of the triangle it
// replaces (paper: 25 degrees). Off in the topology-only mode.
#include "engine/rule.h"
#include "engine/rules/shape_rules.h"

namespace femsimp {
namespace {

class NormalDeviationRule final : public CollapseRule {
 public:
  explicit NormalDeviationRule(double degrees) : cos_min_(CosDeg(degrees)) {}
  Reject reason() const override { return Reject::kNormalDeviation; }
  uint32_t stages() const override { return Stages(RuleStage::kShape); }
  uint32_t cycles_per_face() const override { return 50; }
  bool fan_local() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    return p.geometry.MinNormalCosine() >= cos_min_ ? Verdict::kPass : Verdict::kReject;
  }

 private:
  double cos_min_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeNormalDeviationRule(const SimplifyOptions& o, const RuleSetup&) {
  if (o.topology_only) return nullptr;
  return std::make_unique<NormalDeviationRule>(o.max_normal_deviation_deg);
}

}  // namespace femsimp
