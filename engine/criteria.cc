#include "engine/criteria.h"

#include <cmath>
#include <numbers>

namespace femsimp {
namespace {

DVec3 Sub(const DVec3& a, const DVec3& b) { return a - b; }
double CosDeg(double degrees) { return std::cos(degrees * std::numbers::pi / 180.0); }

}  // namespace

void CollapseGeometry::Build(const Ring& ring, int target_index) {
  const uint32_t vd_index = ring.nbr[target_index];
  const DVec3 v = ToD(ring.center_pos);
  vd = ToD(ring.pos[target_index]);
  const int n = ring.neighbours();
  faces = 0;
  min_normal_cosine_ = 2.0;
  for (int i = 0; i < ring.faces; ++i) {
    const int j = (i + 1) % n;
    if (ring.nbr[i] == vd_index || ring.nbr[j] == vd_index) continue;  // collapsed away
    b[faces] = ToD(ring.pos[i]);
    c[faces] = ToD(ring.pos[j]);
    old_normal[faces] = Cross(Sub(b[faces], v), Sub(c[faces], v));
    new_normal[faces] = Cross(Sub(b[faces], vd), Sub(c[faces], vd));
    ++faces;
  }
}

bool DegenerateCriterion::Accept(const CollapseGeometry& g) const {
  for (int i = 0; i < g.faces; ++i) {
    const double e0 = Dot(Sub(g.b[i], g.vd), Sub(g.b[i], g.vd));
    const double e1 = Dot(Sub(g.c[i], g.vd), Sub(g.c[i], g.vd));
    const double e2 = Dot(Sub(g.c[i], g.b[i]), Sub(g.c[i], g.b[i]));
    const double longest2 = std::max({e0, e1, e2});
    const double area2sq = Dot(g.new_normal[i], g.new_normal[i]);
    if (!(area2sq > 1e-12 * longest2 * longest2)) return false;
  }
  return true;
}

bool FoldOverCriterion::Accept(const CollapseGeometry& g) const {
  for (int i = 0; i < g.faces; ++i)
    if (!(Dot(g.old_normal[i], g.new_normal[i]) > 0.0)) return false;
  return true;
}

MinAngleCriterion::MinAngleCriterion(double degrees) : cos_max_(CosDeg(degrees)) {}

bool MinAngleCriterion::Accept(const CollapseGeometry& g) const {
  for (int i = 0; i < g.faces; ++i) {
    const DVec3* p[3] = {&g.vd, &g.b[i], &g.c[i]};
    for (int k = 0; k < 3; ++k) {
      const DVec3 u = Sub(*p[(k + 1) % 3], *p[k]), w = Sub(*p[(k + 2) % 3], *p[k]);
      const double uu = Dot(u, u), ww = Dot(w, w), uw = Dot(u, w);
      // cos(angle) > cos_max  <=>  angle < min_angle (min_angle < 60 degrees, so cos_max > 0);
      // compared without a square root.
      if (uw > 0.0 && uw * uw > cos_max_ * cos_max_ * uu * ww) return false;
    }
  }
  return true;
}

NormalDeviationCriterion::NormalDeviationCriterion(double degrees) : cos_min_(CosDeg(degrees)) {}

bool NormalDeviationCriterion::Accept(const CollapseGeometry& g) const {
  return g.MinNormalCosine() >= cos_min_;
}

double CollapseGeometry::MinNormalCosine() const {
  if (min_normal_cosine_ <= 1.0) return min_normal_cosine_;
  double worst = 1.0;
  for (int i = 0; i < faces; ++i) {
    const double d = Dot(old_normal[i], new_normal[i]);
    const double nn = Dot(old_normal[i], old_normal[i]) * Dot(new_normal[i], new_normal[i]);
    const double c = nn > 0.0 ? d / std::sqrt(nn) : -1.0;
    worst = std::min(worst, c);
  }
  return min_normal_cosine_ = worst;
}

CriteriaSet CriteriaSet::FromOptions(const SimplifyOptions& options) {
  CriteriaSet set;
  // Degenerate and fold-over triangles break the mesh itself, so they are checked even in
  // the topology-only mode.
  set.criteria_.push_back(std::make_unique<DegenerateCriterion>());
  set.criteria_.push_back(std::make_unique<FoldOverCriterion>());
  if (!options.topology_only) {
    set.criteria_.push_back(std::make_unique<MinAngleCriterion>(options.min_angle_deg));
    set.criteria_.push_back(
        std::make_unique<NormalDeviationCriterion>(options.max_normal_deviation_deg));
  }
  return set;
}

uint32_t CriteriaSet::CyclesPerFace() const {
  uint32_t cycles = 0;
  for (const auto& c : criteria_) cycles += c->cycles_per_face();
  return cycles;
}

bool CriteriaSet::Accept(const CollapseGeometry& g, Reject* failed) const {
  for (const auto& c : criteria_)
    if (!c->Accept(g)) {
      *failed = c->reason();
      return false;
    }
  return true;
}

}  // namespace femsimp
