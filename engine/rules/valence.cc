// The vertices opposite V - Vd keep enough faces: a closed component never shrinks below a
// tetrahedron, an open one never loses its last face.
#include "engine/rule.h"

namespace femsimp {
namespace {

class ValenceRule final : public CollapseRule {
 public:
  Reject reason() const override { return Reject::kValence; }
  uint32_t stages() const override { return Stages(RuleStage::kTopology); }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    for (int k = 0; k < p.deleted; ++k) {
      int faces = 0;
      bool boundary = false;
      if (!p.reader->CountFan(p.opposite[k], 4, &faces, &boundary)) return Verdict::kStale;
      if (faces < (boundary ? 2 : 4)) return Verdict::kReject;
    }
    return Verdict::kPass;
  }
};

}  // namespace

std::unique_ptr<CollapseRule> MakeValenceRule(const SimplifyOptions&, const RuleSetup&) {
  return std::make_unique<ValenceRule>();
}

}  // namespace femsimp
