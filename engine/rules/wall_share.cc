// The wall rule (option max_wall_share; docs/FIDELITY.md § 5): on a thin wall the tolerance is
// at most the given share of the wall's local thickness, so that neither side of it may move by
// enough to change its stiffness much. Each input face gets its own tolerance before the run
// (FaceAttrQ::limit, from the wall thickness under it: engine/wall_thickness.h); the mapped
// bound carries it with its map, a new face taking the least of the old faces it overlaps
// (engine/deviation.h), so that a face's limit is never above that of an input point mapped
// onto it. The rule, checked right after the tolerance rule, keeps each new face's bound
// within its limit.
#include "engine/rule.h"

namespace femsimp {
namespace {

class WallShareRule final : public CollapseRule {
 public:
  Reject reason() const override { return Reject::kWall; }
  uint32_t stages() const override { return Stages(RuleStage::kFidelity); }
  bool reads_face_attrs() const override { return true; }
  bool fan_local() const override { return true; }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    if (p.star != nullptr) {
      const EdgeStar& star = *p.star;
      for (int k = 0; k < star.count; ++k) {
        if (!star.survives[k]) continue;
        if (!Within(k < star.fan_faces ? p.new_attr[k] : p.new_extra_attr[k - star.fan_faces]))
          return Verdict::kReject;
      }
      return Verdict::kPass;
    }
    for (int f = 0; f < p.fan->faces; ++f)
      if (!p.IsDeleted(f) && !Within(p.new_attr[f])) return Verdict::kReject;
    return Verdict::kPass;
  }

 private:
  // A limit of 0: none (the run's tolerance applies, which the tolerance rule keeps).
  static bool Within(const FaceAttrQ& a) { return a.limit == 0.0f || a.error <= a.limit; }
};

}  // namespace

// On where Simplify gave the faces their limits (max_wall_share with a tolerance on a closed
// part) and the mapped bound carries them; the measured check holds each input triangle's
// pieces to its own limit itself (engine/coverage.h), and counts what that refuses as the
// tolerance's.
std::unique_ptr<CollapseRule> MakeWallShareRule(const SimplifyOptions&, const RuleSetup& s) {
  if (!s.wall_limits || s.coverage != nullptr) return nullptr;
  return std::make_unique<WallShareRule>();
}

}  // namespace femsimp
