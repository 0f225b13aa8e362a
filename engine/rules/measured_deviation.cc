// The measured deviation check (option deviation_check = measured; engine/coverage.h): every
// collapse is judged against the input itself, both ways, instead of a bound carried along the
// run. Proposes each new face's measured deviation as its side quadword's error (the deviation
// cost orders candidates by it).
#include <cmath>

#include "engine/coverage.h"
#include "engine/deviation.h"
#include "engine/rule.h"

namespace femsimp {
namespace {

class MeasuredDeviationRule final : public CollapseRule {
 public:
  MeasuredDeviationRule(Coverage* coverage, LineCoverage* lines, double tolerance)
      : coverage_(coverage), lines_(lines), tolerance_(tolerance) {}
  Reject reason() const override { return Reject::kTolerance; }
  uint32_t stages() const override { return Stages(RuleStage::kFidelity); }
  bool reads_face_attrs() const override { return true; }
  // What it reads of the mesh is V's fan (or the star) and the pieces its faces hold, which
  // only a collapse that changes that fan changes.
  bool fan_local() const override { return true; }
  bool keeps_state() const override { return true; }
  // Judged against the input, a vertex off the surface spends nothing later collapses need.
  bool placement_may_pass() const override { return true; }
  // Every piece of the input's lines is held within the tolerance by the line it became
  // (engine/line_coverage.h), wherever the line's vertices go (docs/FIDELITY.md § 11).
  bool holds_placed_lines() const override { return true; }

  Verdict Check(RuleStage, CollapseProposal& p) const override {
    if (p.line_other >= 0) {
      if (!HoldsLine(p)) return Verdict::kReject;
    } else if (p.line_plan != nullptr) {
      p.line_plan->active = false;  // no line moves: the commit has no line pieces to pass on
    }
    if (p.coverage == nullptr) p.coverage = std::make_unique<CoveragePlan>();
    CoveragePlan& plan = *p.coverage;
    const uint32_t star_vd = p.star != nullptr ? p.star->vd_id : kNone;
    if (plan.gathered_star != star_vd) plan.Forget();
    plan.gathered_star = star_vd;
    plan.old_faces.clear();
    plan.fresh_ids.clear();
    DVec3 corners[3 * kMaxStar];
    int fresh = 0;
    if (p.star != nullptr) {
      const EdgeStar& star = *p.star;
      for (int k = 0; k < star.count; ++k) {
        plan.old_faces.push_back(star.face[k]);
        if (!star.survives[k]) continue;
        plan.fresh_ids.push_back(star.face[k]);
        corners[3 * fresh] = star.p;
        corners[3 * fresh + 1] = star.b[k];
        corners[3 * fresh + 2] = star.c[k];
        ++fresh;
      }
    } else {
      const Ring& fan = *p.fan;
      const DVec3 vd = ToD(fan.pos[p.target]);
      for (int f = 0; f < fan.faces; ++f) {
        plan.old_faces.push_back(FaceOf(fan.out[f]));
        if (p.IsDeleted(f)) continue;
        plan.fresh_ids.push_back(FaceOf(fan.out[f]));
        corners[3 * fresh] = vd;
        corners[3 * fresh + 1] = ToD(fan.pos[f]);
        corners[3 * fresh + 2] = ToD(fan.pos[(f + 1) % fan.neighbours()]);
        ++fresh;
      }
    }
    uint64_t work = 0;
    const bool within = coverage_->Judge(
        {corners, size_t(3 * fresh)}, &plan, &work,
        [&](double* certified) { return p.star == nullptr && Certify(p, certified); });
    p.cycles += static_cast<uint32_t>(std::min<uint64_t>(40 * work, 1u << 30));
    if (!within) return Verdict::kReject;
    // The measured deviation of each new face, rounded up, as its error.
    int k = 0;
    if (p.star != nullptr) {
      const EdgeStar& star = *p.star;
      for (int s = 0; s < star.count; ++s) {
        if (!star.survives[s]) continue;
        FaceAttrQ& attr = s < star.fan_faces ? p.new_attr[s] : p.new_extra_attr[s - star.fan_faces];
        attr.error = std::nextafter(static_cast<float>(plan.reach[k++]), 1e30f);
      }
    } else {
      for (int f = 0; f < p.fan->faces; ++f)
        if (!p.IsDeleted(f))
          p.new_attr[f].error = std::nextafter(static_cast<float>(plan.reach[k++]), 1e30f);
    }
    return Verdict::kPass;
  }

  void Commit(CollapseProposal& p) const override {
    coverage_->Apply(*p.coverage);
    if (p.line_plan != nullptr && p.line_plan->active) lines_->Apply(*p.line_plan);
  }
  // The next candidate's faces may be these ids rewritten since.
  void Release(CollapseProposal& p) const override {
    if (p.coverage != nullptr) p.coverage->Forget();
    if (p.line_plan != nullptr) p.line_plan->active = false;
  }

 private:
  // V slides along its line onto Vd (L - V - Vd becomes L - Vd), or V and Vd on one line merge
  // at P (L - V - Vd - Vd' becomes L - P - Vd'): the old edges' pieces go to the new ones.
  bool HoldsLine(CollapseProposal& p) const {
    if (p.line_plan == nullptr) p.line_plan = std::make_unique<LinePlan>();
    LinePlan& plan = *p.line_plan;
    plan.active = false;
    const Ring& fan = *p.fan;
    const uint32_t v = fan.center, vd = fan.nbr[p.target], l = fan.nbr[p.line_other];
    const DVec3 at_l = ToD(fan.pos[p.line_other]);
    plan.old_edges[0] = {l, v};
    plan.old_edges[1] = {v, vd};
    plan.fresh_edges[0] = {l, vd};
    plan.fresh_from[0] = at_l;
    if (p.star == nullptr) {
      plan.old_count = 2;
      plan.fresh_count = 1;
      plan.fresh_to[0] = ToD(fan.pos[p.target]);
    } else {
      const Ring& other = *p.target_fan;
      int beyond = -1;  // Vd's other line neighbour
      for (int a = 0; a < other.neighbours(); ++a)
        if (other.feature[a] && other.nbr[a] != v) beyond = a;
      if (beyond < 0) return false;
      plan.old_edges[2] = {vd, other.nbr[beyond]};
      plan.old_count = 3;
      plan.fresh_to[0] = p.star->p;
      plan.fresh_edges[1] = {vd, other.nbr[beyond]};
      plan.fresh_from[1] = p.star->p;
      plan.fresh_to[1] = ToD(other.pos[beyond]);
      plan.fresh_count = 2;
    }
    uint64_t work = 0;
    const bool held = lines_->Judge(&plan, &work);
    p.cycles += static_cast<uint32_t>(40 * work);
    plan.active = held;
    return held;
  }

  // Part (b) for a half-edge collapse without measuring: every point of an old face lies within
  // its error of the input (the errors this rule gave), which BoundReach carries to the new
  // faces. certified[k]: new face k's bound (in the order the faces are given to Judge); false
  // when the overlay cannot be built or certifies no face within the tolerance.
  bool Certify(const CollapseProposal& p, double* certified) const {
    const Ring& fan = *p.fan;
    double old_reach[kMaxRing], new_reach[kMaxRing];
    for (int f = 0; f < fan.faces; ++f) old_reach[f] = p.fan_attr[f].error;
    if (!BoundReach(fan, p.target, p.line_other, old_reach, new_reach)) return false;
    int k = 0;
    bool any = false;
    for (int f = 0; f < fan.faces; ++f) {
      if (p.IsDeleted(f)) continue;
      certified[k] = new_reach[f];
      any |= certified[k] <= tolerance_;
      ++k;
    }
    return any;
  }

  Coverage* coverage_;
  LineCoverage* lines_;
  double tolerance_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeMeasuredDeviationRule(const RuleSetup& s) {
  if (s.coverage == nullptr) return nullptr;
  return std::make_unique<MeasuredDeviationRule>(s.coverage, s.lines, s.tolerance);
}

}  // namespace femsimp
