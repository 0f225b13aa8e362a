// The guaranteed deviation bound (docs/FIDELITY.md, engine/deviation.h): every surviving fan
// face's bound after the collapse stays within the tolerance. Proposes the new bounds.
#include "engine/deviation.h"
#include "engine/rule.h"

namespace femsimp {
namespace {

class DeviationBoundRule final : public CollapseRule {
 public:
  explicit DeviationBoundRule(float tolerance) : tolerance_(tolerance) {}
  Reject reason() const override { return Reject::kTolerance; }
  uint32_t stages() const override { return Stages(RuleStage::kFidelity); }
  bool reads_face_attrs() const override { return true; }
  bool fan_local() const override { return true; }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    if (p.star != nullptr) return CheckStar(p);
    const int nf = p.fan->faces;
    float old_error[kMaxRing] = {}, new_error[kMaxRing];
    for (int f = 0; f < nf; ++f) old_error[f] = p.fan_attr[f].error;
    int work = 0;
    const bool bounded =
        BoundDeviation(*p.fan, p.target, p.line_other, old_error, new_error, &work);
    p.cycles += static_cast<uint32_t>(24 * work);
    if (!bounded) return Verdict::kReject;
    for (int f = 0; f < nf; ++f) {
      if (p.IsDeleted(f)) continue;
      if (new_error[f] > tolerance_) return Verdict::kReject;
      p.new_attr[f].error = new_error[f];
    }
    return Verdict::kPass;
  }

 private:
  Verdict CheckStar(CollapseProposal& p) const {
    const EdgeStar& star = *p.star;
    float old_error[kMaxStar], new_error[kMaxStar];
    for (int k = 0; k < star.count; ++k)
      old_error[k] =
          k < star.fan_faces ? p.fan_attr[k].error : p.extra_attr[k - star.fan_faces].error;
    int work = 0;
    const bool bounded = BoundStarDeviation(star, old_error, new_error, &work);
    p.cycles += static_cast<uint32_t>(24 * work);
    if (!bounded) return Verdict::kReject;
    for (int k = 0; k < star.count; ++k) {
      if (!star.survives[k]) continue;
      if (new_error[k] > tolerance_) return Verdict::kReject;
      FaceAttrQ& attr = k < star.fan_faces ? p.new_attr[k] : p.new_extra_attr[k - star.fan_faces];
      attr.error = new_error[k];
    }
    return Verdict::kPass;
  }

  float tolerance_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeDeviationBoundRule(const SimplifyOptions&, const RuleSetup& s) {
  if (!(s.tolerance > 0.0f)) return nullptr;
  return std::make_unique<DeviationBoundRule>(s.tolerance);
}

}  // namespace femsimp
