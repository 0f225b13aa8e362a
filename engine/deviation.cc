#include "engine/deviation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "engine/vec.h"

namespace femsimp {
namespace {

using P2 = PlanePoint;
P2 Sub2(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
double Cross2(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
double Orient(P2 a, P2 b, P2 c) { return Cross2(Sub2(b, a), Sub2(c, a)); }
double AngleAt(P2 a, P2 b, P2 c) {  // angle b-a-c
  const P2 u = Sub2(b, a), w = Sub2(c, a);
  return std::atan2(std::fabs(Cross2(u, w)), u.x * w.x + u.y * w.y);
}

// A triangle of a layout with its edges' directions and lengths, which the overlap test reads
// for every triangle of the other layout: computed once.
struct LaidTriangle {
  P2 corner[3];
  P2 edge[3];  // corner[e] -> corner[e + 1]
  double length[3];
  void Set(P2 a, P2 b, P2 c) {
    corner[0] = a;
    corner[1] = b;
    corner[2] = c;
    for (int e = 0; e < 3; ++e) {
      edge[e] = Sub2(corner[(e + 1) % 3], corner[e]);
      length[e] = std::sqrt(edge[e].x * edge[e].x + edge[e].y * edge[e].y);  // no overflow
    }
  }
};

// Interiors of two counter-clockwise triangles intersect (touching within eps counts, so the
// test errs towards overlap: a larger, still valid bound).
bool Overlap(const LaidTriangle& t, const LaidTriangle& u, double eps) {
  const LaidTriangle* tri[2] = {&t, &u};
  for (int s = 0; s < 2; ++s) {
    const LaidTriangle& a = *tri[s];
    const LaidTriangle& b = *tri[1 - s];
    for (int e = 0; e < 3; ++e) {
      // b entirely on the outer (right) side of edge e separates them.
      bool separated = true;
      for (int k = 0; k < 3 && separated; ++k)
        separated = Cross2(a.edge[e], Sub2(b.corner[k], a.corner[e])) < -eps * a.length[e];
      if (separated) return false;
    }
  }
  return true;
}

// Two unit vectors spanning the plane perpendicular to the unit normal n.
void PlaneBasis(const DVec3& n, DVec3* u, DVec3* w) {
  const DVec3 helper = std::fabs(n.x) < 0.6 ? DVec3{1, 0, 0} : DVec3{0, 1, 0};
  *u = Cross(n, helper);
  *u = (1.0 / Norm(*u)) * *u;
  *w = Cross(n, *u);
}

// Barycentric coordinates of p in (a, b, c), given twice its signed area.
void Barycentric(P2 p, P2 a, P2 b, P2 c, double area2, double* l) {
  l[0] = Orient(p, b, c) / area2;
  l[1] = Orient(a, p, c) / area2;
  l[2] = 1.0 - l[0] - l[1];
}

// The steps phi_new(p) - phi_old(p) at the corners of one overlay cell: their box and the
// longest (the step is affine on the cell, so both hold for every point of it).
struct StepBox {
  DVec3 lo{0, 0, 0}, hi{0, 0, 0};
  double longest = 0.0;
  bool empty = true;
  void Add(const DVec3& d) {
    if (empty) {
      lo = hi = d;
      empty = false;
    } else {
      lo = {std::min(lo.x, d.x), std::min(lo.y, d.y), std::min(lo.z, d.z)};
      hi = {std::max(hi.x, d.x), std::max(hi.y, d.y), std::max(hi.z, d.z)};
    }
    longest = std::max(longest, Norm(d));
  }
};

// A new face's displacement, gathered over the cells it is made of: phi_new(p) - p =
// (phi_old(p) - p) + step, so the box is the old box plus the cell's steps (a Minkowski sum of
// boxes) and the length at most the old bound plus the longest step.
struct NewDisplacement {
  Displacement d;
  bool any = false;
  void AddCell(const Displacement& old, const StepBox& cell) {
    if (cell.empty) return;  // the triangles only touch: their points lie in other cells too
    d.limit = std::min(d.limit, old.limit);
    const DVec3 lo = old.lo + cell.lo, hi = old.hi + cell.hi;
    if (!any) {
      d.lo = lo;
      d.hi = hi;
      d.bound = old.bound + cell.longest;
      any = true;
      return;
    }
    d.lo = {std::min(d.lo.x, lo.x), std::min(d.lo.y, lo.y), std::min(d.lo.z, lo.z)};
    d.hi = {std::max(d.hi.x, hi.x), std::max(d.hi.y, hi.y), std::max(d.hi.z, hi.z)};
    d.bound = std::max(d.bound, old.bound + cell.longest);
  }
  // Widened by eps for rounding; the bound is the tighter of the two it knows.
  Displacement Finish(double eps) const {
    Displacement out = d;
    out.lo -= DVec3{eps, eps, eps};
    out.hi += DVec3{eps, eps, eps};
    out.bound = std::min(d.bound + eps, out.Reach());
    // Every displacement is within the bound of 0, so the box can shrink to that cube.
    out.lo = {std::max(out.lo.x, -out.bound), std::max(out.lo.y, -out.bound),
              std::max(out.lo.z, -out.bound)};
    out.hi = {std::min(out.hi.x, out.bound), std::min(out.hi.y, out.bound),
              std::min(out.hi.z, out.bound)};
    return out;
  }
};

// The reach of the box [d.lo + s, d.hi + s].
double ShiftedReach(Displacement d, const DVec3& s) {
  d.lo += s;
  d.hi += s;
  return d.Reach();
}

}  // namespace

double Displacement::Reach() const {
  const double x = std::max(std::fabs(lo.x), std::fabs(hi.x));
  const double y = std::max(std::fabs(lo.y), std::fabs(hi.y));
  const double z = std::max(std::fabs(lo.z), std::fabs(hi.z));
  return std::sqrt(x * x + y * y + z * z);
}

void LayOutFan(const Ring& ring, FanLayout* layout) {
  const int n = ring.neighbours();
  const int nf = ring.faces;
  FanLayout& l = *layout;
  l.v = ToD(ring.center_pos);
  for (int k = 0; k < n; ++k) l.p[k] = ToD(ring.pos[k]);
  DVec3 normal{0, 0, 0};
  for (int f = 0; f < nf; ++f) normal += Cross(l.p[f] - l.v, l.p[(f + 1) % n] - l.v);
  const double nlen = Norm(normal);
  l.ok = nlen > 0.0;
  if (!l.ok) return;
  PlaneBasis((1.0 / nlen) * normal, &l.u, &l.w);
  l.scale = 0.0;
  for (int k = 0; k < n; ++k) {
    l.q[k] = {Dot(l.p[k] - l.v, l.u), Dot(l.p[k] - l.v, l.w)};
    l.scale = std::max(l.scale, std::sqrt(l.q[k].x * l.q[k].x + l.q[k].y * l.q[k].y));
  }
  l.angle_at_v = -1.0;
  l.eps_len = 1e-9 * l.scale;
  l.eps_area = 1e-12 * l.scale * l.scale;
  l.winds_around_v = true;
  for (int f = 0; f < nf && l.winds_around_v; ++f)
    l.winds_around_v = Orient({0, 0}, l.q[f], l.q[(f + 1) % n]) > l.eps_area;
}

bool LayOutDirection(const Ring& ring, const FanLayout& layout, int target, int line_other,
                     const Displacement* old_moved, double limit, DirectionLayout* d, int* work) {
  const int n = ring.neighbours();
  const int nf = ring.faces;
  if (ring.boundary && line_other < 0) return false;  // boundary vertices slide along it only
  if (!layout.ok) return false;
  const DVec3& v = layout.v;
  const DVec3* p = layout.p;
  const P2* q = layout.q;
  const double eps_area = layout.eps_area;

  // Where V goes: itself, or its closest point on the new feature edge (line_other, target).
  DVec3 vp = v;
  if (line_other >= 0) {
    const DVec3 a = p[line_other], e = p[target] - p[line_other];
    const double s = Dot(v - a, e) / Dot(e, e);
    if (!(s > 1e-6 && s < 1.0 - 1e-6)) return false;  // V' would sit on a line vertex
    vp = a + s * e;
  }
  const P2 v2 = {Dot(vp - v, layout.u), Dot(vp - v, layout.w)};
  d->v2 = v2;

  // Old layout: fan faces with V at V', every one counter-clockwise. New layout: the surviving
  // faces with Vd for V, tiling the same polygon from Vd.
  if (line_other < 0) {
    if (!layout.winds_around_v) return false;
  } else {
    for (int f = 0; f < nf; ++f)
      if (!(Orient(v2, q[f], q[(f + 1) % n]) > eps_area)) return false;
  }
  const P2 qd = q[target];
  d->qd = qd;
  for (int f = 0; f < nf; ++f) {
    const int b = f, c = (f + 1) % n;
    d->survives[f] = b != target && c != target;
    if (d->survives[f] && !(Orient(qd, q[b], q[c]) > eps_area)) return false;
  }

  // The step at V', on the new face(s) holding its position.
  bool placed = false;
  bool inside[kMaxRing];  // V' lies in the face's interior, clear of its edges
  for (int f = 0; f < nf; ++f) {
    d->holds_v[f] = false;
    if (!d->survives[f]) continue;
    const int b = f, c = (f + 1) % n;
    double l[3];
    Barycentric(v2, qd, q[b], q[c], Orient(qd, q[b], q[c]), l);
    if (l[0] < -1e-9 || l[1] < -1e-9 || l[2] < -1e-9) continue;
    const DVec3 at = l[0] * p[target] + l[1] * p[b] + l[2] * p[c];
    d->step_v[f] = at - v;
    d->holds_v[f] = true;
    inside[f] = l[0] > 1e-7 && l[1] > 1e-7 && l[2] > 1e-7;
    placed = true;
  }
  if (!placed) return false;

  // Refused early when V' alone takes a new face beyond the limit. The cell of old face f and
  // new face g holding V' has the step at V' for a corner when they overlap, and then g's bound
  // is at least the smaller of f's bound plus |step| and the reach of f's box shifted by the
  // step (NewDisplacement). Where the layouts tile (the turns below) some old face overlaps g
  // (the old fan covers all around V'), so the least of that over the fan is a floor for g's
  // bound; where V' is inside g, every old face (each has V' for a corner) overlaps g, and the
  // most over the fan of either part is. Where they do not tile, the collapse is refused anyway.
  for (int g = 0; g < nf; ++g) {
    if (!d->holds_v[g]) continue;
    const DVec3 s = d->step_v[g];
    const double step = Norm(s);
    double floor = std::numeric_limits<double>::infinity();
    if (inside[g]) {
      double plus_step = 0.0, reach = 0.0;
      for (int f = 0; f < nf; ++f) {
        plus_step = std::max(plus_step, old_moved[f].bound + step);
        reach = std::max(reach, ShiftedReach(old_moved[f], s));
      }
      floor = std::min(plus_step, reach);
    } else {
      for (int f = 0; f < nf && floor > limit; ++f)
        floor = std::min(floor, std::min(old_moved[f].bound + step, ShiftedReach(old_moved[f], s)));
    }
    if (floor > limit) {
      *work = nf;
      return false;
    }
  }
  return true;
}

bool BoundDeviation(const Ring& ring, int target, int line_other, const Displacement* old_moved,
                    double limit, Displacement* new_moved, int* work) {
  FanLayout layout;
  LayOutFan(ring, &layout);
  DirectionLayout direction;
  if (!LayOutDirection(ring, layout, target, line_other, old_moved, limit, &direction, work))
    return false;
  return BoundDeviation(ring, layout, direction, target, old_moved, limit, new_moved, work);
}

bool BoundDeviation(const Ring& ring, const FanLayout& layout, const DirectionLayout& d, int target,
                    const Displacement* old_moved, double limit, Displacement* new_moved,
                    int* work) {
  const int n = ring.neighbours();
  const int nf = ring.faces;
  const DVec3& v = layout.v;
  const DVec3* p = layout.p;
  const P2* q = layout.q;
  const double scale = layout.scale, eps_len = layout.eps_len;
  const P2 v2 = d.v2, qd = d.qd;
  const bool* survives = d.survives;
  const bool* holds_v = d.holds_v;
  const DVec3* step_v = d.step_v;

  // The old layout winds once around V' (half a turn on a boundary, where V' lies on the
  // straight new boundary edge), and the new one turns around Vd as the old one did.
  const auto angle_around = [&](P2 at) {
    double sum = 0.0;
    for (int f = 0; f < nf; ++f) sum += AngleAt(at, q[f], q[(f + 1) % n]);
    return sum;
  };
  const bool at_v = v2.x == 0.0 && v2.y == 0.0;  // the same sum for every such direction
  if (at_v && layout.angle_at_v < 0.0) layout.angle_at_v = angle_around(v2);
  const double angle_v = at_v ? layout.angle_at_v : angle_around(v2);
  double angle_vd_old = 0.0, angle_vd_new = 0.0;
  for (int f = 0; f < nf; ++f) {
    const int b = f, c = (f + 1) % n;
    if (b == target) angle_vd_old += AngleAt(q[b], q[c], v2);
    if (c == target) angle_vd_old += AngleAt(q[c], v2, q[b]);
  }
  const double full = ring.boundary ? std::numbers::pi : 2.0 * std::numbers::pi;
  if (std::fabs(angle_v - full) > 1e-6) return false;
  for (int f = 0; f < nf; ++f)
    if (survives[f]) angle_vd_new += AngleAt(qd, q[f], q[(f + 1) % n]);
  if (std::fabs(angle_vd_new - angle_vd_old) > 1e-6) return false;

  // Where old spoke V' -> k crosses new spoke Vd -> j, the step there (false: no crossing).
  const auto crossing = [&](int k, int j, DVec3* step) {
    const P2 dk = Sub2(q[k], v2), dj = Sub2(q[j], qd);
    const double denom = Cross2(dk, dj);
    if (std::fabs(denom) <= 1e-15 * scale * scale) return false;  // parallel: meet at ends only
    const P2 r = Sub2(qd, v2);
    const double s = Cross2(r, dj) / denom, t = Cross2(r, dk) / denom;
    if (s < -1e-9 || s > 1 + 1e-9 || t < -1e-9 || t > 1 + 1e-9) return false;
    *step = (p[target] + t * (p[j] - p[target])) - (v + s * (p[k] - v));
    return true;
  };

  // On each cell (old face f) x (new face g) of the overlay the step is affine, so it is held by
  // the box of its values at the cell's corners: V' (when g holds it), a link vertex the two
  // faces share (0: link vertices do not move) and the spoke crossings.
  struct Box {
    double lo_x, lo_y, hi_x, hi_y;
  };
  const auto box = [](P2 a, P2 b, P2 c) {
    return Box{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::max({a.x, b.x, c.x}),
               std::max({a.y, b.y, c.y})};
  };
  Box old_box[kMaxRing];
  // Off the stack: an SPE software thread's is small (engine/cell_backend.cc); its software
  // threads switch only at DMA waits, never inside this function.
  thread_local LaidTriangle old_laid[kMaxRing];
  for (int f = 0; f < nf; ++f) {
    old_box[f] = box(v2, q[f], q[(f + 1) % n]);
    old_laid[f].Set(v2, q[f], q[(f + 1) % n]);
  }
  int tests = nf;
  for (int g = 0; g < nf; ++g) {
    if (!survives[g]) continue;
    const int g2 = (g + 1) % n;
    LaidTriangle tg;
    tg.Set(qd, q[g], q[g2]);
    const Box gb = box(qd, q[g], q[g2]);
    NewDisplacement moved;
    for (int f = 0; f < nf; ++f) {
      const int f2 = (f + 1) % n;
      const Box& fb = old_box[f];
      if (fb.lo_x > gb.hi_x + eps_len || gb.lo_x > fb.hi_x + eps_len ||
          fb.lo_y > gb.hi_y + eps_len || gb.lo_y > fb.hi_y + eps_len)
        continue;  // cannot overlap
      ++tests;
      if (!Overlap(old_laid[f], tg, eps_len)) continue;
      StepBox cell;
      if (holds_v[g]) cell.Add(step_v[g]);
      for (int k : {f, f2})
        if (k == target || k == g || k == g2) cell.Add({0, 0, 0});
      for (int k : {f, f2}) {
        if (k == target) continue;
        for (int j : {g, g2}) {
          if (j == target || j == k) continue;
          ++tests;
          DVec3 step;
          if (crossing(k, j, &step)) cell.Add(step);
        }
      }
      moved.AddCell(old_moved[f], cell);
    }
    new_moved[g] = moved.Finish(eps_len);
    // A face's bound only grows with its cells: one beyond the limit refuses the collapse, and
    // the faces after it need not be laid over.
    if (new_moved[g].bound > limit) {
      *work = tests;
      return false;
    }
  }
  *work = tests;
  return true;
}

bool BoundReach(const Ring& ring, int target, int line_other, const double* old_reach,
                double* new_reach) {
  // Off the stack: an SPE software thread's is small (the cell back end never runs this).
  thread_local Displacement old_moved[kMaxRing], new_moved[kMaxRing];
  for (int f = 0; f < ring.faces; ++f) {
    const double e = old_reach[f];
    old_moved[f].bound = e;
    old_moved[f].lo = {-e, -e, -e};
    old_moved[f].hi = {e, e, e};
  }
  int work = 0;
  if (!BoundDeviation(ring, target, line_other, old_moved, std::numeric_limits<double>::infinity(),
                      new_moved, &work))
    return false;
  const int n = ring.neighbours();
  for (int f = 0; f < ring.faces; ++f)
    if (f != target && (f + 1) % n != target) new_reach[f] = new_moved[f].bound;
  return true;
}

namespace {

// A triangle of one of the two layouts: its plane corners and the surface points they lift to.
struct Lifted {
  P2 q[3];
  DVec3 p[3];
  double area2;
  DVec3 At(P2 x) const {
    double l[3];
    Barycentric(x, q[0], q[1], q[2], area2, l);
    return l[0] * p[0] + l[1] * p[1] + l[2] * p[2];
  }
  bool Holds(P2 x) const {
    double l[3];
    Barycentric(x, q[0], q[1], q[2], area2, l);
    return l[0] >= -1e-9 && l[1] >= -1e-9 && l[2] >= -1e-9;
  }
};

// The steps over the overlay cell of old triangle f and new triangle g (their projections
// overlap), at the corners of the cell: corners of one inside the other or crossings of their
// edges.
StepBox CellSteps(const Lifted& f, const Lifted& g, double scale, int* tests) {
  StepBox cell;
  const auto at = [&](P2 x) { cell.Add(g.At(x) - f.At(x)); };
  for (int k = 0; k < 3; ++k) {
    if (g.Holds(f.q[k])) at(f.q[k]);
    if (f.Holds(g.q[k])) at(g.q[k]);
  }
  for (int i = 0; i < 3; ++i) {
    const P2 a0 = f.q[i], da = Sub2(f.q[(i + 1) % 3], a0);
    for (int j = 0; j < 3; ++j) {
      ++*tests;
      const P2 b0 = g.q[j], db = Sub2(g.q[(j + 1) % 3], b0);
      const double denom = Cross2(da, db);
      if (std::fabs(denom) <= 1e-15 * scale * scale) continue;  // parallel: corners cover it
      const P2 r = Sub2(b0, a0);
      const double s = Cross2(r, db) / denom, t = Cross2(r, da) / denom;
      if (s < -1e-9 || s > 1 + 1e-9 || t < -1e-9 || t > 1 + 1e-9) continue;
      at({a0.x + s * da.x, a0.y + s * da.y});
    }
  }
  return cell;
}

// The point of segment a - b nearest q, kept off the segment's ends (a laid point there would
// make a triangle of the layout flat).
DVec3 NearestInside(const DVec3& a, const DVec3& b, const DVec3& q) {
  const DVec3 d = b - a;
  const double len2 = Dot(d, d);
  const double t = len2 > 0.0 ? Dot(q - a, d) / len2 : 0.5;
  return a + std::clamp(t, 0.02, 0.98) * d;
}

}  // namespace

bool BoundStarDeviation(const EdgeStar& star, const Displacement* old_moved,
                        Displacement* new_moved, int* work) {
  DVec3 normal{0, 0, 0};
  for (int k = 0; k < star.count; ++k)
    normal += Cross(star.b[k] - star.a[k], star.c[k] - star.a[k]);
  const double nlen = Norm(normal);
  if (!(nlen > 0.0)) return false;
  DVec3 u, w;
  PlaneBasis((1.0 / nlen) * normal, &u, &w);
  const DVec3 origin = 0.5 * (star.v + star.vd);
  double scale = Norm(star.hi - star.lo);
  if (!(scale > 0.0)) return false;
  const auto plane = [&](const DVec3& x) { return P2{Dot(x - origin, u), Dot(x - origin, w)}; };
  const double eps_len = 1e-9 * scale, eps_area = 1e-12 * scale * scale;

  // Where V and Vd are laid. On a line L - V - Vd - R, which becomes L - P - R, the old layout
  // must put the old line where the new one is: V at its nearest point of L - P, Vd at its
  // nearest of P - R, and a point X of V - Vd at P, which splits the two faces on V - Vd.
  // Points of the same layout position still correspond, and the line goes onto the line.
  const P2 p2 = plane(star.p);
  P2 v2 = plane(star.v), vd2 = plane(star.vd);
  DVec3 x{0, 0, 0};
  if (star.on_line) {
    v2 = plane(NearestInside(star.line_v_end, star.p, star.v));
    vd2 = plane(NearestInside(star.p, star.line_vd_end, star.vd));
    x = NearestInside(star.v, star.vd, star.p);
  }

  // Both layouts, each checked to tile the link polygon once. Off the stack (an SPE software
  // thread's is small), per OS thread: the software threads of an SPE switch only at DMA waits,
  // never inside this function.
  enum Corner { kOther, kV, kVd, kX };
  thread_local Lifted old_t[kMaxStar + 2], new_t[kMaxStar];
  thread_local int source[kMaxStar + 2];  // the star face an old layout triangle is part of
  int laid = 0;
  double angle[4] = {0, 0, 0, 0};  // summed at V, Vd and X, by Corner
  const auto lay_old = [&](int k, const DVec3(&p)[3], const Corner(&corner)[3]) {
    Lifted& t = old_t[laid];
    for (int i = 0; i < 3; ++i) {
      t.p[i] = p[i];
      t.q[i] = corner[i] == kV ? v2 : corner[i] == kVd ? vd2 : corner[i] == kX ? p2 : plane(p[i]);
    }
    t.area2 = Orient(t.q[0], t.q[1], t.q[2]);
    if (!(t.area2 > eps_area)) return false;
    for (int i = 0; i < 3; ++i)
      if (corner[i] != kOther)
        angle[corner[i]] += AngleAt(t.q[i], t.q[(i + 1) % 3], t.q[(i + 2) % 3]);
    source[laid++] = k;
    return true;
  };
  double angle_p = 0.0;
  for (int k = 0; k < star.count; ++k) {
    const DVec3 p[3] = {star.a[k], star.b[k], star.c[k]};
    const Corner corner[3] = {k < star.fan_faces ? kV : kVd,
                              star.b_id[k] == star.vd_id ? kVd : kOther,
                              star.c_id[k] == star.vd_id ? kVd : kOther};
    if (star.on_line && !star.survives[k]) {
      // (V, .., ..) with Vd one of the others: the part on V's side (Vd replaced by X) and the
      // part on Vd's (V replaced by X).
      DVec3 near_v[3] = {p[0], p[1], p[2]}, near_vd[3] = {x, p[1], p[2]};
      Corner v_side[3] = {corner[0], corner[1], corner[2]}, vd_side[3] = {kX, corner[1], corner[2]};
      for (int i = 1; i < 3; ++i)
        if (corner[i] == kVd) {
          near_v[i] = x;
          v_side[i] = kX;
        }
      if (!lay_old(k, near_v, v_side) || !lay_old(k, near_vd, vd_side)) return false;
    } else if (!lay_old(k, p, corner)) {
      return false;
    }
    if (!star.survives[k]) continue;
    Lifted& n = new_t[k];
    n.p[0] = star.p;
    n.p[1] = star.b[k];
    n.p[2] = star.c[k];
    n.q[0] = p2;
    n.q[1] = plane(star.b[k]);
    n.q[2] = plane(star.c[k]);
    n.area2 = Orient(n.q[0], n.q[1], n.q[2]);
    if (!(n.area2 > eps_area)) return false;
    angle_p += AngleAt(p2, n.q[1], n.q[2]);
  }
  const double full = 2.0 * std::numbers::pi;
  if (std::fabs(angle[kV] - full) > 1e-6 || std::fabs(angle[kVd] - full) > 1e-6 ||
      (star.on_line && std::fabs(angle[kX] - full) > 1e-6) || std::fabs(angle_p - full) > 1e-6)
    return false;

  thread_local LaidTriangle old_laid[kMaxStar + 2];  // off the stack, as the layouts above
  for (int f = 0; f < laid; ++f) old_laid[f].Set(old_t[f].q[0], old_t[f].q[1], old_t[f].q[2]);
  int tests = 0;
  for (int g = 0; g < star.count; ++g) {
    if (!star.survives[g]) continue;
    LaidTriangle new_laid;
    new_laid.Set(new_t[g].q[0], new_t[g].q[1], new_t[g].q[2]);
    NewDisplacement moved;
    for (int f = 0; f < laid; ++f) {
      ++tests;
      if (!Overlap(old_laid[f], new_laid, eps_len)) continue;
      moved.AddCell(old_moved[source[f]], CellSteps(old_t[f], new_t[g], scale, &tests));
    }
    new_moved[g] = moved.Finish(eps_len);
  }
  *work = tests;
  return true;
}

}  // namespace femsimp
