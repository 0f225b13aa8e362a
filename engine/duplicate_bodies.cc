#include "engine/duplicate_bodies.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "engine/facet_box_grid.h"
#include "engine/point_in_shell.h"
#include "engine/surfaces.h"
#include "engine/triangle_distance.h"
#include "engine/vec.h"

namespace femsimp {
namespace {

struct Shell {
  std::vector<uint32_t> faces;
  bool closed = true;  // each edge has two of its facets, running it opposite ways
  double volume = 0;   // signed, as the facets are oriented
  double area = 0;
  double moment[3] = {0, 0, 0};  // area times centroid
  std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  double Thickness() const { return area > 0 ? 2 * std::abs(volume) / area : 0.0; }
};

DVec3 At(const float* positions, uint32_t v) {
  const float* p = positions + 3 * size_t(v);
  return {p[0], p[1], p[2]};
}

bool BoxesWithin(const Shell& a, const Shell& b, double d) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(a.lo[k] - b.lo[k]) > d || std::abs(a.hi[k] - b.hi[k]) > d) return false;
  return true;
}

// One shell's surface, for the other shells' samples: how far each lies from it (a grid of its
// facets' boxes) and whether it lies outside it (its winding number, built when first asked).
class ShellProbe {
 public:
  ShellProbe(const float* positions, std::span<const uint32_t> tri,
             const std::vector<uint8_t>& parity, const Shell& shell)
      : positions_(positions),
        tri_(tri),
        parity_(parity),
        faces_(shell.faces),
        grid_(Boxes(positions, tri, shell)) {}

  // Whether every corner and facet centroid of `from` lies within d of this shell: the farthest
  // such distance is raised into *farthest, and *outside set where one of them farther than
  // `on` lies outside it. A corner is asked once however many facets share it.
  bool Holds(const Shell& from, double d, double on, double* farthest, bool* outside) {
    if (++stamp_ == 0) {
      std::fill(asked_.begin(), asked_.end(), 0);
      stamp_ = 1;
    }
    const auto holds = [&](const DVec3& q) {
      const double d2 = SquaredDistance(q, d);
      if (!(d2 <= d * d)) return false;
      *farthest = std::max(*farthest, std::sqrt(d2));
      if (!*outside && d2 > on * on) *outside = Inside().Winding(q) == 0;
      return true;
    };
    for (uint32_t f : from.faces) {
      DVec3 centroid{0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        const uint32_t v = tri_[3 * size_t(f) + i];
        const DVec3 p = At(positions_, v);
        centroid += (1.0 / 3) * p;
        if (v >= asked_.size()) asked_.resize(v + 1, 0);
        if (asked_[v] == stamp_) continue;
        asked_[v] = stamp_;
        if (!holds(p)) return false;
      }
      if (!holds(centroid)) return false;
    }
    return true;
  }

 private:
  static std::vector<FacetBox> Boxes(const float* positions, std::span<const uint32_t> tri,
                                     const Shell& shell) {
    std::vector<FacetBox> boxes;
    boxes.reserve(shell.faces.size());
    for (uint32_t f : shell.faces) {
      FacetBox b{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
          const double x = positions[3 * size_t(tri[3 * f + i]) + k];
          b.lo[k] = std::min(b.lo[k], x);
          b.hi[k] = std::max(b.hi[k], x);
        }
      boxes.push_back(b);
    }
    return boxes;
  }
  // The squared distance from q to the nearest facet within d of it (HUGE_VAL: none). Asked
  // about a small box first: a facet found within its half-width is the nearest (any nearer one
  // meets the box too), and copies lie close, so most points need no more.
  double SquaredDistance(const DVec3& q, double d) {
    double best = HUGE_VAL;
    for (double r = d / 64;; r = std::min(d, 8 * r)) {
      const FacetBox around{{q.x - r, q.y - r, q.z - r}, {q.x + r, q.y + r, q.z + r}};
      grid_.ForEachMeeting(around, [&](uint32_t i) {
        const uint32_t* t = &tri_[3 * size_t(faces_[i])];
        best =
            std::min(best, SquaredDistanceToTriangle(q, At(positions_, t[0]), At(positions_, t[1]),
                                                     At(positions_, t[2])));
      });
      if (best <= r * r || r >= d) return best;
    }
  }
  const PointInShell& Inside() {
    if (!inside_) {
      std::vector<uint32_t> corners;
      corners.reserve(3 * faces_.size());
      for (uint32_t f : faces_) {  // turned as the shell's first facet
        const uint32_t* t = &tri_[3 * size_t(f)];
        corners.insert(corners.end(), {t[0], parity_[f] ? t[2] : t[1], parity_[f] ? t[1] : t[2]});
      }
      inside_ = std::make_unique<PointInShell>(positions_, std::move(corners));
    }
    return *inside_;
  }

  const float* positions_;
  std::span<const uint32_t> tri_;
  const std::vector<uint8_t>& parity_;
  const std::vector<uint32_t>& faces_;
  FacetBoxGrid grid_;
  std::unique_ptr<PointInShell> inside_;
  std::vector<uint32_t> asked_;  // per vertex: the stamp of the last Holds that asked it
  uint32_t stamp_ = 0;
};

}  // namespace

std::vector<DuplicateBody> FindDuplicateBodies(const float* positions,
                                               std::span<const uint32_t> tri,
                                               std::span<const uint32_t> edge_of,
                                               std::span<const uint32_t> edge_uses,
                                               double max_offset) {
  const uint32_t nf = static_cast<uint32_t>(tri.size() / 3);
  if (max_offset <= 0 || nf == 0) return {};
  const Surfaces surfaces = FindSurfaces(tri, edge_of, edge_uses);
  std::vector<Shell> shells(surfaces.count());
  // (edge, shell, +1 or -1 by direction) for the half-edges on seams: a shell is closed where
  // each seam it is on carries two of its facets, running it opposite ways.
  struct SeamUse {
    uint32_t edge, shell;
    int direction;
    bool operator<(const SeamUse& o) const {
      return edge != o.edge ? edge < o.edge : shell < o.shell;
    }
  };
  std::vector<SeamUse> on_seams;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t id = surfaces.of_facet[f];
    Shell& s = shells[id];
    s.faces.push_back(f);
    s.closed &= surfaces.orientable[id] != 0;
    const bool turned = surfaces.parity[f] != 0;  // runs against the shell's first facet
    DVec3 p[3];
    for (int i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i, e = edge_of[h], uses = edge_uses[e];
      p[i] = At(positions, tri[h]);
      s.closed &= uses != 1;
      if (uses > 2)  // its direction once turned as the shell's first facet
        on_seams.push_back({e, id, (tri[h] < tri[3 * f + (i + 1) % 3]) != turned ? 1 : -1});
      const double x[3] = {p[i].x, p[i].y, p[i].z};
      for (int k = 0; k < 3; ++k) {
        s.lo[k] = std::min(s.lo[k], x[k]);
        s.hi[k] = std::max(s.hi[k], x[k]);
      }
    }
    // Volume about the shell's first corner, which keeps the sum's rounding to the shell's size.
    const DVec3 o = At(positions, tri[3 * s.faces[0]]);
    const DVec3 a = p[0] - o, b = p[1] - o, c = p[2] - o;
    s.volume += (turned ? -1 : 1) * Dot(a, Cross(b, c)) / 6;
    const DVec3 n = Cross(p[1] - p[0], p[2] - p[0]);
    const double area = 0.5 * Norm(n);
    s.area += area;
    const DVec3 centroid = (1.0 / 3) * (p[0] + p[1] + p[2]);
    s.moment[0] += area * centroid.x;
    s.moment[1] += area * centroid.y;
    s.moment[2] += area * centroid.z;
  }
  std::sort(on_seams.begin(), on_seams.end());
  for (size_t i = 0; i < on_seams.size();) {
    size_t j = i;
    int sum = 0;
    while (j < on_seams.size() && on_seams[j].edge == on_seams[i].edge &&
           on_seams[j].shell == on_seams[i].shell)
      sum += on_seams[j++].direction;
    shells[on_seams[i].shell].closed &= j - i == 2 && sum == 0;
    i = j;
  }

  std::vector<uint32_t> closed;  // by first facet
  for (uint32_t id = 0; id < shells.size(); ++id)
    if (shells[id].closed && shells[id].area > 0 && shells[id].volume != 0) closed.push_back(id);
  if (closed.size() < 2) return {};
  std::vector<uint32_t> by_x = closed;  // for the shells whose box starts near another's
  std::sort(by_x.begin(), by_x.end(),
            [&](uint32_t a, uint32_t b) { return shells[a].lo[0] < shells[b].lo[0]; });
  std::vector<std::unique_ptr<ShellProbe>> probes(shells.size());
  const auto probe = [&](uint32_t id) -> ShellProbe& {
    if (!probes[id])
      probes[id] = std::make_unique<ShellProbe>(positions, tri, surfaces.parity, shells[id]);
    return *probes[id];
  };
  const auto reach = [&](uint32_t a, uint32_t b) {
    return max_offset * std::min(shells[a].Thickness(), shells[b].Thickness());
  };
  // Whether b repeats a: within d of each other, and crossing each other (each has a sample
  // outside the other): a shell inside another near its surface is the wall of a thin cavity
  // or of a coating, not a copy.
  const auto repeats = [&](uint32_t b, uint32_t a, double* farthest) {
    const double d = reach(a, b), on = 1e-6 * d;
    bool b_out = false, a_out = false;
    *farthest = 0;
    return BoxesWithin(shells[a], shells[b], d) &&
           probe(a).Holds(shells[b], d, on, farthest, &b_out) &&
           probe(b).Holds(shells[a], d, on, farthest, &a_out) && b_out && a_out;
  };
  std::vector<uint8_t> removed(shells.size(), 0);
  const auto near = [&](uint32_t id, double d, auto&& visit) {
    const auto first = std::lower_bound(by_x.begin(), by_x.end(), shells[id].lo[0] - d,
                                        [&](uint32_t a, double x) { return shells[a].lo[0] < x; });
    for (auto it = first; it != by_x.end() && shells[*it].lo[0] <= shells[id].lo[0] + d; ++it)
      if (*it != id && !removed[*it] && visit(*it)) return true;
    return false;
  };
  std::vector<DuplicateBody> copies;
  for (uint32_t id : closed) {
    const Shell& copy = shells[id];
    double farthest = 0;
    uint32_t kept_id = 0;
    const bool found = near(id, max_offset * copy.Thickness(), [&](uint32_t other) {
      if (other > id || !repeats(id, other, &farthest)) return false;  // the earlier one is kept
      // A third shell near both that repeats neither lies between or around them: layers (a
      // coating's walls over a part), not copies.
      const double d = reach(id, other);
      double unused = 0;
      const bool layered = near(id, d, [&](uint32_t third) {
        return third != other && BoxesWithin(shells[third], shells[other], d) &&
               BoxesWithin(shells[third], copy, d) && !repeats(third, other, &unused) &&
               !repeats(third, id, &unused);
      });
      kept_id = other;
      return !layered;
    });
    if (!found) continue;
    removed[id] = 1;
    const Shell& kept = shells[kept_id];
    DuplicateBody& out = copies.emplace_back();
    out.faces = copy.faces;
    out.kept_face = kept.faces[0];
    out.kept_faces = static_cast<uint32_t>(kept.faces.size());
    out.distance = farthest;
    out.thickness = std::min(copy.Thickness(), kept.Thickness());
    out.volume = std::abs(copy.volume);
    for (int k = 0; k < 3; ++k) out.centre[k] = copy.moment[k] / copy.area;
  }
  return copies;
}

}  // namespace femsimp
