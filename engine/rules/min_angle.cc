// Every interior angle of every new triangle at least min_angle_deg (paper: 10 degrees), or, in
// the default relaxed form, the new triangles' smallest angle no smaller than the smallest angle
// of the triangles they replace (V's whole fan, and Vd's for a full-edge collapse): on a
// sliver-rich CAD export, where most triangles are below any useful threshold, collapses may then
// only improve the worst angle, instead of none being allowed at all. Off in the topology-only
// mode and at 0 degrees.
#include <algorithm>

#include "engine/rule.h"
#include "engine/rules/shape_rules.h"

namespace femsimp {
namespace {

// cos^2 of the triangle's smallest angle (its smallest angle is below 90 degrees, where a
// larger cosine means a smaller angle); 1 for a degenerate triangle.
double SmallestAngleCos2(const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3* q[3] = {&a, &b, &c};
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    const DVec3 u = *q[(k + 1) % 3] - *q[k], w = *q[(k + 2) % 3] - *q[k];
    const double uu = Dot(u, u), ww = Dot(w, w), uw = Dot(u, w);
    if (!(uu > 0.0 && ww > 0.0)) return 1.0;
    if (uw > 0.0) worst = std::max(worst, uw * uw / (uu * ww));
  }
  return worst;
}

class MinAngleRule final : public CollapseRule {
 public:
  MinAngleRule(double degrees, bool strict) : cos_max_(CosDeg(degrees)), strict_(strict) {}
  Reject reason() const override { return Reject::kMinAngle; }
  uint32_t stages() const override { return Stages(RuleStage::kShape); }
  uint32_t cycles_per_face() const override { return strict_ ? 60 : 110; }
  bool fan_local() const override { return true; }
  Verdict Check(RuleStage, CollapseProposal& p) const override {
    return (strict_ ? MeetsThreshold(p.geometry) : MeetsThresholdOrImproves(p)) ? Verdict::kPass
                                                                                : Verdict::kReject;
  }

 private:
  bool MeetsThreshold(const CollapseGeometry& g) const {
    for (int i = 0; i < g.faces; ++i) {
      const DVec3* q[3] = {&g.vd, &g.b[i], &g.c[i]};
      for (int k = 0; k < 3; ++k) {
        const DVec3 u = *q[(k + 1) % 3] - *q[k], w = *q[(k + 2) % 3] - *q[k];
        const double uu = Dot(u, u), ww = Dot(w, w), uw = Dot(u, w);
        // cos(angle) > cos_max  <=>  angle < min_angle (min_angle < 60 degrees, so
        // cos_max > 0); compared without a square root.
        if (uw > 0.0 && uw * uw > cos_max_ * cos_max_ * uu * ww) return false;
      }
    }
    return true;
  }

  bool MeetsThresholdOrImproves(CollapseProposal& p) const {
    const CollapseGeometry& g = p.geometry;
    double worst_new = 0.0;
    for (int i = 0; i < g.faces; ++i)
      worst_new = std::max(worst_new, SmallestAngleCos2(g.vd, g.b[i], g.c[i]));
    if (worst_new <= cos_max_ * cos_max_) return true;
    if (p.fan_smallest_angle_cos2 < 0.0) {
      const Ring& fan = *p.fan;
      const DVec3 v = ToD(fan.center_pos);
      double fan_worst = 0.0;
      for (int f = 0; f < fan.faces; ++f)
        fan_worst = std::max(
            fan_worst,
            SmallestAngleCos2(v, ToD(fan.pos[f]), ToD(fan.pos[(f + 1) % fan.neighbours()])));
      p.fan_smallest_angle_cos2 = fan_worst;
    }
    double worst_old = p.fan_smallest_angle_cos2;
    // A full-edge collapse also replaces Vd's other faces.
    for (int i = g.fan_faces; i < g.faces; ++i)
      worst_old = std::max(worst_old, SmallestAngleCos2(g.old_apex[i], g.b[i], g.c[i]));
    return worst_new <= worst_old;
  }

  double cos_max_;  // an angle is too small when its cosine exceeds this
  bool strict_;
};

}  // namespace

std::unique_ptr<CollapseRule> MakeMinAngleRule(const SimplifyOptions& o, const RuleSetup&) {
  // At 0 degrees both forms hold for every triangle (a new one too thin to measure is the
  // degenerate rule's): the rule would only spend its angles.
  if (o.topology_only || o.min_angle_deg <= 0.0) return nullptr;
  return std::make_unique<MinAngleRule>(o.min_angle_deg, o.strict_min_angle);
}

}  // namespace femsimp
