// No new triangle may be (almost) flat. Checked in every mode: a degenerate triangle breaks
// the mesh itself.
#include <algorithm>

#include "engine/rule.h"

namespace femsimp {
namespace {

class DegenerateRule final : public CollapseRule {
 public:
  Reject reason() const override { return Reject::kDegenerate; }
  uint32_t stages() const override { return Stages(RuleStage::kShape); }
  uint32_t cycles_per_face() const override { return 20; }
  bool fan_local() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    const CollapseGeometry& g = p.geometry;
    for (int i = 0; i < g.faces; ++i) {
      const double e0 = Dot(g.b[i] - g.vd, g.b[i] - g.vd);
      const double e1 = Dot(g.c[i] - g.vd, g.c[i] - g.vd);
      const double e2 = Dot(g.c[i] - g.b[i], g.c[i] - g.b[i]);
      const double longest2 = std::max({e0, e1, e2});
      const double area2sq = Dot(g.new_normal[i], g.new_normal[i]);
      if (!(area2sq > 1e-12 * longest2 * longest2)) return Verdict::kReject;
    }
    return Verdict::kPass;
  }
};

}  // namespace

std::unique_ptr<CollapseRule> MakeDegenerateRule(const SimplifyOptions&, const RuleSetup&) {
  return std::make_unique<DegenerateRule>();
}

}  // namespace femsimp
