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

// A triangle's corners a, b, c: at each, the dot product of the two edges from it and their
// squared lengths (in the order next corner, then the one after). Each edge is subtracted once
// and negated where a corner needs it the other way round: negation is exact, so every figure is
// bitwise the one the two edges from the corner give.
struct Corners {
  double uw[3], uu[3], ww[3];
  Corners(const DVec3& a, const DVec3& b, const DVec3& c) {
    const DVec3 ab = b - a, bc = c - b, ca = a - c;
    const double lab = Dot(ab, ab), lbc = Dot(bc, bc), lca = Dot(ca, ca);
    uw[0] = -Dot(ab, ca), uu[0] = lab, ww[0] = lca;
    uw[1] = -Dot(bc, ab), uu[1] = lbc, ww[1] = lab;
    uw[2] = -Dot(ca, bc), uu[2] = lca, ww[2] = lbc;
  }
};

// cos^2 of the triangle's smallest angle (its smallest angle is below 90 degrees, where a
// larger cosine means a smaller angle); 1 for a degenerate triangle.
double SmallestAngleCos2(const DVec3& a, const DVec3& b, const DVec3& c) {
  const Corners t(a, b, c);
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (!(t.uu[k] > 0.0 && t.ww[k] > 0.0)) return 1.0;
    if (t.uw[k] > 0.0) worst = std::max(worst, t.uw[k] * t.uw[k] / (t.uu[k] * t.ww[k]));
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
      const Corners t(g.vd, g.b[i], g.c[i]);
      for (int k = 0; k < 3; ++k) {
        // cos(angle) > cos_max  <=>  angle < min_angle (min_angle < 60 degrees, so
        // cos_max > 0); compared without a square root.
        if (t.uw[k] > 0.0 && t.uw[k] * t.uw[k] > cos_max_ * cos_max_ * t.uu[k] * t.ww[k])
          return false;
      }
    }
    return true;
  }

  bool MeetsThresholdOrImproves(CollapseProposal& p) const {
    const CollapseGeometry& g = p.geometry;
    const double threshold = cos_max_ * cos_max_;
    double worst_new = 0.0, worst_old = -1.0;  // worst_old: not needed yet
    for (int i = 0; i < g.faces; ++i) {
      const double cos2 = SmallestAngleCos2(g.vd, g.b[i], g.c[i]);
      worst_new = std::max(worst_new, cos2);
      // A new face below the threshold and worse than every old one refuses the collapse
      // whatever the other new faces are.
      if (cos2 > threshold) {
        if (worst_old < 0.0) worst_old = WorstOld(p);
        if (cos2 > worst_old) return false;
      }
    }
    if (worst_new <= threshold) return true;
    return worst_new <= worst_old;
  }

  // cos^2 of the smallest angle of the triangles the collapse replaces.
  static double WorstOld(CollapseProposal& p) {
    const CollapseGeometry& g = p.geometry;
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
    return worst_old;
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
