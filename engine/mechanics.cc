#include "engine/mechanics.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace femsimp {
namespace {

DVec3 Pos(const VertexQ& q) { return {q.x, q.y, q.z}; }

// Solves (m + mu I) x = r for a symmetric positive semi-definite m (Cramer's rule).
DVec3 Solve3(const double m[3][3], const DVec3& r) {
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  if (!(std::fabs(det) > 0.0)) return {0, 0, 0};
  const double b[3] = {r.x, r.y, r.z};
  double x[3];
  for (int c = 0; c < 3; ++c) {
    double a[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a[i][j] = j == c ? b[i] : m[i][j];
    x[c] = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
            a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
            a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])) /
           det;
  }
  return {x[0], x[1], x[2]};
}

// A fan's or star's change, measured with its faces' orientation, as the ledger takes it: the
// solid's by the faces' weight, the parts' on their sides as it is (enclosed).
void SetMassDelta(const MassProperties& d, bool closed, double weight, uint32_t sides,
                  CollapseDelta* delta) {
  delta->mass = d;
  delta->sides = sides;
  delta->enclosed = closed ? d.measure : 0.0;
  if (closed && weight != 1.0) {
    delta->mass.measure *= weight;
    delta->mass.moment = weight * d.moment;
  }
}

}  // namespace

GroupIndex::GroupIndex(const Mesh& mesh) {
  const HalfEdgeQ* h = mesh.halfedges();
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (h[3 * f].flags & kFaceRemoved) continue;
    if (index_.try_emplace(h[3 * f].group, static_cast<int>(ids_.size())).second)
      ids_.push_back(h[3 * f].group);
  }
}

bool IsClosed(const Mesh& mesh) {
  const HalfEdgeQ* h = mesh.halfedges();
  for (uint32_t e = 0; e < mesh.halfedge_capacity(); ++e)
    if (!(h[e].flags & kFaceRemoved) && h[e].twin == kNone) return false;
  return true;
}

MassProperties MeasureMass(const Mesh& mesh, bool closed, const DVec3& origin) {
  MassProperties m;
  const VertexQ* v = mesh.vertices();
  const HalfEdgeQ* h = mesh.halfedges();
  const std::vector<FaceSides>& sides = mesh.sides();
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (h[3 * f].flags & kFaceRemoved) continue;
    const DVec3 a = Pos(v[h[3 * f + 2].target]), b = Pos(v[h[3 * f].target]),
                c = Pos(v[h[3 * f + 1].target]);
    if (closed) {  // signed tetrahedron with the origin
      const double weight = sides.empty() ? 1.0 : sides[Mesh::SidesOf(h[3 * f])].weight;
      if (weight == 0.0) continue;
      const double vol = weight * Dot(a, Cross(b, c)) / 6.0;
      m.measure += vol;
      m.moment += (vol / 4.0) * (a + b + c);
      // Tetrahedra with their apex at `origin` (near the part, so no large cancelling terms)
      // sum to the same solid as those from the world origin.
      const DVec3 ao = a - origin, bo = b - origin, co = c - origin;
      m.second +=
          TetrahedronSecondMoment({0, 0, 0}, ao, bo, co, weight * Dot(ao, Cross(bo, co)) / 6.0);
    } else {
      const double area = 0.5 * Norm(Cross(b - a, c - a));
      m.measure += area;
      m.moment += (area / 3.0) * (a + b + c);
      m.second += TriangleSecondMoment(a - origin, b - origin, c - origin, area);
    }
  }
  return m;
}

std::vector<double> MeasurePartVolumes(const Mesh& mesh, const DVec3& origin) {
  std::vector<double> volumes;
  const std::vector<FaceSides>& sides = mesh.sides();
  for (const FaceSides& s : sides)
    volumes.resize(std::max<size_t>(volumes.size(), std::max(s.behind, s.ahead) + 1), 0.0);
  if (volumes.empty()) return volumes;
  const VertexQ* v = mesh.vertices();
  const HalfEdgeQ* h = mesh.halfedges();
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (h[3 * f].flags & kFaceRemoved) continue;
    const FaceSides& s = sides[Mesh::SidesOf(h[3 * f])];
    if (s.behind == kSpace && s.ahead == kSpace) continue;
    const DVec3 a = Pos(v[h[3 * f + 2].target]) - origin, b = Pos(v[h[3 * f].target]) - origin,
                c = Pos(v[h[3 * f + 1].target]) - origin;
    const double vol = Dot(a, Cross(b, c)) / 6.0;
    if (s.behind != kSpace) volumes[s.behind] += vol;
    if (s.ahead != kSpace) volumes[s.ahead] -= vol;
  }
  return volumes;
}

double SurfaceArea(const Mesh& mesh) {
  const VertexQ* v = mesh.vertices();
  const HalfEdgeQ* h = mesh.halfedges();
  double area = 0.0;
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (h[3 * f].flags & kFaceRemoved) continue;
    const DVec3 a = Pos(v[h[3 * f + 2].target]), b = Pos(v[h[3 * f].target]),
                c = Pos(v[h[3 * f + 1].target]);
    area += 0.5 * Norm(Cross(b - a, c - a));
  }
  return area;
}

MassProperties MovedSecondMoment(const MassProperties& m, const DVec3& from, const DVec3& to) {
  // J_to = J_from - m d^T - d m^T + M d d^T, with m the first moment about `from`, d = to - from.
  const DVec3 first = m.moment - m.measure * from, d = to - from;
  MassProperties out = m;
  // (The cross term directly: first and d differ in size by the mass, so a difference of
  // outer products of their sum loses one of them at a large or a tiny mass.)
  out.second = m.second + m.measure * Outer(d) - SymmetricProduct(first, d);
  return out;
}

MassSummary Summarize(const MassProperties& m, bool solid, const DVec3& origin) {
  MassSummary s;
  s.solid = solid;
  s.measure = m.measure;
  if (m.measure == 0.0) return s;
  s.centroid = m.centroid();
  const Eigen3 e = Eigen(InertiaOf(MovedSecondMoment(m, origin, s.centroid).second));
  for (int i = 0; i < 3; ++i) {
    s.principal_moments[i] = e.values[i];
    s.principal_axes[i] = e.axes[i];
  }
  return s;
}

FieldResultants MeasureFields(const Mesh& mesh, const GroupIndex& groups) {
  FieldResultants r;
  const size_t fields = mesh.field_names().size();
  if (fields == 0) return r;
  r.force.assign(groups.size() * kMaxFaceFields, DVec3{0, 0, 0});
  r.load.assign(groups.size() * kMaxFaceFields, 0.0);
  const VertexQ* v = mesh.vertices();
  const HalfEdgeQ* h = mesh.halfedges();
  const FaceAttrQ* attr = mesh.face_attrs();
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (h[3 * f].flags & kFaceRemoved) continue;
    const DVec3 a = Pos(v[h[3 * f + 2].target]), b = Pos(v[h[3 * f].target]),
                c = Pos(v[h[3 * f + 1].target]);
    const DVec3 area = 0.5 * Cross(b - a, c - a);
    const int g = groups.Of(h[3 * f].group);
    for (size_t k = 0; k < fields; ++k) {
      const double p = attr[f].field[k];
      r.force[g * kMaxFaceFields + k] += p * area;
      r.load[g * kMaxFaceFields + k] += std::fabs(p) * Norm(area);
    }
  }
  return r;
}

double WorstFieldChange(const FieldResultants& before, const FieldResultants& after) {
  double worst = 0.0;
  for (size_t i = 0; i < before.force.size() && i < after.force.size(); ++i) {
    const double change = Norm(after.force[i] - before.force[i]);
    if (before.load[i] > 0.0) worst = std::max(worst, change / before.load[i]);
  }
  return worst;
}

void CollapseMassDelta(const Ring& ring, int target, bool closed, double weight,
                       CollapseDelta* delta) {
  const int n = ring.neighbours();
  const DVec3 v = ToD(ring.center_pos), vd = ToD(ring.pos[target]);
  MassProperties d;
  for (int f = 0; f < ring.faces; ++f) {
    const DVec3 b = ToD(ring.pos[f]), c = ToD(ring.pos[(f + 1) % n]);
    if (closed) {  // tetrahedra from Vd: the new faces contain Vd and contribute nothing
      const double vol = Dot(v - vd, Cross(b - vd, c - vd)) / 6.0;
      d.measure -= vol;
      d.moment -= (vol / 4.0) * (vd + v + b + c);
    } else {
      const double old_area = 0.5 * Norm(Cross(b - v, c - v));
      d.measure -= old_area;
      d.moment -= (old_area / 3.0) * (v + b + c);
      if (f != target && (f + 1) % n != target) {
        const double new_area = 0.5 * Norm(Cross(b - vd, c - vd));
        d.measure += new_area;
        d.moment += (new_area / 3.0) * (vd + b + c);
      }
    }
  }
  SetMassDelta(d, closed, weight, ring.sides, delta);
}

void CollapseSecondMomentDelta(const Ring& ring, int target, bool closed, double weight,
                               const DVec3& origin, CollapseDelta* delta) {
  const int n = ring.neighbours();
  const DVec3 v = ToD(ring.center_pos) - origin, vd = ToD(ring.pos[target]) - origin;
  Sym3& d = delta->mass.second;
  for (int f = 0; f < ring.faces; ++f) {
    const DVec3 b = ToD(ring.pos[f]) - origin, c = ToD(ring.pos[(f + 1) % n]) - origin;
    if (closed) {  // the tetrahedra between the old and the new faces, as in CollapseMassDelta
      d -= TetrahedronSecondMoment(vd, v, b, c, weight * Dot(v - vd, Cross(b - vd, c - vd)) / 6.0);
    } else {
      d -= TriangleSecondMoment(v, b, c, 0.5 * Norm(Cross(b - v, c - v)));
      if (f != target && (f + 1) % n != target)
        d += TriangleSecondMoment(vd, b, c, 0.5 * Norm(Cross(b - vd, c - vd)));
    }
  }
}

void StarMassDelta(const EdgeStar& star, bool closed, double weight, uint32_t sides,
                   CollapseDelta* delta) {
  // Closed: tetrahedra from the edge's midpoint (near the patch, so no large terms cancel);
  // both patches share their border, so the sum does not depend on that point.
  const DVec3 o = 0.5 * (star.v + star.vd);
  MassProperties d;
  const auto add = [&](const DVec3& a, const DVec3& b, const DVec3& c, double sign) {
    if (closed) {
      const double vol = sign * Dot(a - o, Cross(b - o, c - o)) / 6.0;
      d.measure += vol;
      d.moment += (vol / 4.0) * (o + a + b + c);
    } else {
      const double area = sign * 0.5 * Norm(Cross(b - a, c - a));
      d.measure += area;
      d.moment += (area / 3.0) * (a + b + c);
    }
  };
  for (int k = 0; k < star.count; ++k) {
    add(star.a[k], star.b[k], star.c[k], -1.0);
    if (star.survives[k]) add(star.p, star.b[k], star.c[k], 1.0);
  }
  SetMassDelta(d, closed, weight, sides, delta);
}

void StarSecondMomentDelta(const EdgeStar& star, bool closed, double weight, const DVec3& origin,
                           CollapseDelta* delta) {
  const DVec3 o = 0.5 * (star.v + star.vd) - origin;
  Sym3& d = delta->mass.second;
  const auto add = [&](DVec3 a, DVec3 b, DVec3 c, bool added) {
    a = a - origin;
    b = b - origin;
    c = c - origin;
    const Sym3 j =
        closed ? TetrahedronSecondMoment(o, a, b, c, weight * Dot(a - o, Cross(b - o, c - o)) / 6.0)
               : TriangleSecondMoment(a, b, c, 0.5 * Norm(Cross(b - a, c - a)));
    if (added)
      d += j;
    else
      d -= j;
  };
  for (int k = 0; k < star.count; ++k) {
    add(star.a[k], star.b[k], star.c[k], false);
    if (star.survives[k]) add(star.p, star.b[k], star.c[k], true);
  }
}

void TransferFields(const Ring& ring, int target, int fields, const FaceAttrQ* fan_attr,
                    const int* group_slot, FaceAttrQ* new_attr, CollapseDelta* delta) {
  const int n = ring.neighbours();
  const DVec3 v = ToD(ring.center_pos), vd = ToD(ring.pos[target]);
  DVec3 old_area[kMaxRing], new_area[kMaxRing];
  bool survives[kMaxRing];
  for (int f = 0; f < ring.faces; ++f) {
    const DVec3 b = ToD(ring.pos[f]), c = ToD(ring.pos[(f + 1) % n]);
    old_area[f] = 0.5 * Cross(b - v, c - v);
    survives[f] = f != target && (f + 1) % n != target;
    new_area[f] = survives[f] ? 0.5 * Cross(b - vd, c - vd) : DVec3{0, 0, 0};
    new_attr[f] = fan_attr[f];
  }
  delta->entries = 0;
  int seen[kMaxRing];
  int groups = 0;
  for (int f = 0; f < ring.faces; ++f) {
    bool known = false;
    for (int i = 0; i < groups; ++i) known |= seen[i] == group_slot[f];
    if (!known) seen[groups++] = group_slot[f];
  }
  for (int gi = 0; gi < groups && gi < 2; ++gi) {  // a movable vertex borders at most two groups
    const int group = seen[gi];
    for (int k = 0; k < fields; ++k) {
      DVec3 before{0, 0, 0}, unchanged{0, 0, 0};
      double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
      for (int f = 0; f < ring.faces; ++f) {
        if (group_slot[f] != group) continue;
        before += static_cast<double>(fan_attr[f].field[k]) * old_area[f];
        if (!survives[f]) continue;
        unchanged += static_cast<double>(fan_attr[f].field[k]) * new_area[f];
        const double len = Norm(new_area[f]);
        const double a[3] = {new_area[f].x, new_area[f].y, new_area[f].z};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) m[i][j] += a[i] * a[j] / len;
      }
      // A value uniform over the group's fan (the usual pressure boundary condition) stays
      // exactly as given; only the geometry's change of its resultant is charged. A varying
      // field is adjusted, regularised: a direction the new faces barely span gets a small
      // correction and the rest is charged to the budget, rather than wild values.
      bool uniform = true;
      float first = 0.0f;
      bool have_first = false;
      for (int f = 0; f < ring.faces && uniform; ++f) {
        if (group_slot[f] != group) continue;
        if (!have_first) {
          first = fan_attr[f].field[k];
          have_first = true;
        }
        uniform = fan_attr[f].field[k] == first;
      }
      const double mu = 1e-4 * (m[0][0] + m[1][1] + m[2][2]);
      for (int i = 0; i < 3; ++i) m[i][i] += mu;
      const DVec3 lambda = uniform ? DVec3{0, 0, 0} : Solve3(m, before - unchanged);
      DVec3 after{0, 0, 0};
      for (int f = 0; f < ring.faces; ++f) {
        if (group_slot[f] != group || !survives[f]) continue;
        const double p = uniform
                             ? fan_attr[f].field[k]
                             : fan_attr[f].field[k] + Dot(new_area[f], lambda) / Norm(new_area[f]);
        new_attr[f].field[k] = static_cast<float>(p);
        after += static_cast<double>(new_attr[f].field[k]) * new_area[f];
      }
      delta->slot[delta->entries] = group * static_cast<int>(kMaxFaceFields) + k;
      delta->force[delta->entries++] = after - before;
    }
  }
}

MechanicsLedger::MechanicsLedger(const MassProperties& input, const FieldResultants& fields,
                                 std::vector<FaceSides> sides, std::vector<double> part_volumes)
    : input_(input),
      fields_(fields),
      force_spent_(fields.force.size()),
      sides_(std::move(sides)),
      part_input_(std::move(part_volumes)),
      part_spent_(part_input_.size(), 0.0) {
  for (DVec3& f : force_spent_) f = {0, 0, 0};
}

bool MechanicsLedger::TryCommit(uint32_t v, const CollapseDelta& delta, const CollapseDelta& judged,
                                absl::FunctionRef<bool(const LedgerView&)> within) {
  std::lock_guard<std::mutex> lock(mu_);
  MassProperties spent;
  if (!within(ViewWith(judged, &spent))) return false;
  if (in_round_)
    round_deltas_.emplace_back(v, delta);
  else
    Add(delta);
  return true;
}

bool MechanicsLedger::TryCommitTogether(
    std::span<const CollapseDelta> deltas, std::span<const CollapseDelta> judged,
    absl::FunctionRef<bool(const LedgerView&, size_t k)> within) {
  std::lock_guard<std::mutex> lock(mu_);
  MassProperties spent;
  for (size_t k = 0; k < deltas.size(); ++k)
    if (!within(ViewWith(judged[k], &spent), k)) return false;
  for (const CollapseDelta& delta : deltas) Add(delta);
  return true;
}

LedgerView MechanicsLedger::ViewWith(const CollapseDelta& judged, MassProperties* spent) const {
  // A delta without a measured mass change adds zeros.
  *spent = spent_;
  spent->measure += judged.mass.measure;
  spent->moment += judged.mass.moment;
  spent->second += judged.mass.second;
  LedgerView view{input_, *spent, fields_, force_spent_};
  if (!sides_.empty()) {
    const FaceSides& s = sides_[judged.sides];
    for (const auto& [part, sign] : {std::pair(s.behind, 1.0), std::pair(s.ahead, -1.0)})
      if (part != kSpace)
        view.parts[view.part_count++] = {part_input_[part],
                                         part_spent_[part] + sign * judged.enclosed};
  }
  return view;
}

void MechanicsLedger::Add(const CollapseDelta& delta) {
  spent_.measure += delta.mass.measure;
  spent_.moment += delta.mass.moment;
  spent_.second += delta.mass.second;
  if (!sides_.empty()) {
    const FaceSides& s = sides_[delta.sides];
    if (s.behind != kSpace) part_spent_[s.behind] += delta.enclosed;
    if (s.ahead != kSpace) part_spent_[s.ahead] -= delta.enclosed;
  }
  for (int i = 0; i < delta.entries; ++i) force_spent_[delta.slot[i]] += delta.force[i];
}

void MechanicsLedger::BeginRound(size_t winners) {
  in_round_ = true;
  round_scale_ = static_cast<double>(std::max<size_t>(1, winners));
  round_deltas_.clear();
}

void MechanicsLedger::EndRound() {
  std::sort(round_deltas_.begin(), round_deltas_.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [v, delta] : round_deltas_) Add(delta);
  round_deltas_.clear();
  in_round_ = false;
  round_scale_ = 1.0;
}

CollapseDelta Scaled(const CollapseDelta& delta, double s) {
  CollapseDelta out = delta;
  out.mass.measure *= s;
  out.mass.moment = s * out.mass.moment;
  out.mass.second = s * out.mass.second;
  out.enclosed *= s;
  for (int i = 0; i < out.entries; ++i) out.force[i] = s * out.force[i];
  return out;
}

}  // namespace femsimp
