// Every interior angle of every new triangle at least min_angle_deg (paper: 10 degrees). Off in
// the topology-only mode.
#include "engine/rule.h"
#include "engine/rules/shape_rules.h"

namespace femsimp {
namespace {

class MinAngleRule final : public CollapseRule {
 public:
  explicit MinAngleRule(double degrees) : cos_max_(CosDeg(degrees)) {}
  Reject reason() const override { return Reject::kMinAngle; }
  uint32_t stages() const override { return Stages(RuleStage::kShape); }
  uint32_t cycles_per_face() const override { return 60; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const CollapseGeometry& g = p.geometry;
    for (int i = 0; i < g.faces; ++i) {
      const DVec3* q[3] = {&g.vd, &g.b[i], &g.c[i]};
      for (int k = 0; k < 3; ++k) {
        const DVec3 u = *q[(k + 1) % 3] - *q[k], w = *q[(k + 2) % 3] - *q[k];
        const double uu = Dot(u, u), ww = Dot(w, w), uw = Dot(u, w);
        // cos(angle) > cos_max  <=>  angle < min_angle (min_angle < 60 degrees, so
        // cos_max > 0); compared without a square root.
        if (uw > 0.0 && uw * uw > cos_max_ * cos_max_ * uu * ww) return Verdict::kReject;
      }
    }
    return Verdict::kPass;
  }

 private:
  double cos_max_;  // an angle is too small when its cosine exceeds this
};

}  // namespace

std::unique_ptr<CollapseRule> MakeMinAngleRule(const SimplifyOptions& o, const RuleSetup&) {
  if (o.topology_only) return nullptr;
  return std::make_unique<MinAngleRule>(o.min_angle_deg);
}

}  // namespace femsimp
