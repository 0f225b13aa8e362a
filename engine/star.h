// The edge star of a full-edge collapse (option placement = optimal; engine/kernel.h): V and Vd
// merge into one vertex placed at P. The old patch is V's fan and Vd's fan (the two faces on the
// edge V - Vd counted once); the new patch is P's fan over the same link, one new face per old
// face that survives, with V or Vd replaced by P. The rules judge the collapse on it (its
// shape, deviation bound and mass change), and the kernel commits it under the locks of V's and
// Vd's one-rings.
#pragma once

#include <algorithm>
#include <cstdint>

#include "engine/ring.h"
#include "engine/vec.h"

namespace femsimp {

// A star wider than a fan may be is left to the half-edge collapse (the kernel's state lives in
// an SPE's local store on the cell back end; a fan of 64 is never seen in CAD).
inline constexpr int kMaxStar = kMaxRing;

// How far beyond the box of V, Vd and their one-rings P may go, as a fraction of the box's
// longest side, on every axis. Where the surface bends, the point that keeps the volume lies
// off the patch, often outside the box along the axis the patch is thin in (docs/FIDELITY.md
// § 11); the round scheduler widens the box of each of a candidate's stars the same way, so P
// stays where the round's locks and boxes reach.
inline constexpr double kPlacementReach = 0.25;

// `box` widened by kPlacementReach of its longest side on every axis.
inline void WidenForPlacement(DVec3* lo, DVec3* hi) {
  const DVec3 side = *hi - *lo;
  const double reach = kPlacementReach * std::max({side.x, side.y, side.z});
  *lo = *lo - DVec3{reach, reach, reach};
  *hi = *hi + DVec3{reach, reach, reach};
}

struct EdgeStar {
  // Old face k is (a[k], b[k], c[k]), counter-clockwise, with a[k] = V or Vd; when it survives,
  // its new face is (p, b[k], c[k]). The first fan_faces are V's fan faces in fan order (face k
  // is fan face k, the two on V - Vd among them); the rest are Vd's other faces.
  int count = 0;
  int fan_faces = 0;
  DVec3 a[kMaxStar], b[kMaxStar], c[kMaxStar];
  bool survives[kMaxStar];
  uint32_t face[kMaxStar];                                  // face ids
  uint32_t a_id[kMaxStar], b_id[kMaxStar], c_id[kMaxStar];  // vertex ids of the corners
  uint32_t vd_id = kNone;                                   // the vertex that stays, at p
  DVec3 v{0, 0, 0}, vd{0, 0, 0};                            // where V and Vd are
  DVec3 p{0, 0, 0};
  // V and Vd on one feature line, L - V - Vd - R, which becomes L - P - R: L and R, so that
  // the deviation bound maps the old line onto the new one (BoundStarDeviation).
  bool on_line = false;
  DVec3 line_v_end{0, 0, 0}, line_vd_end{0, 0, 0};  // L and R
  // The box of V, Vd and their one-rings, widened for placement (WidenForPlacement): P stays
  // in it, so that everything the collapse creates lies where its locks and the round
  // scheduler's boxes reach.
  DVec3 lo{0, 0, 0}, hi{0, 0, 0};

  // Builds the star of V = fan.center and Vd = fan.nbr[target], whose one-ring is target_fan.
  // line_other: V's other feature neighbour (fan index) when V - Vd is an edge of the line V
  // slides along, or -1; Vd's other feature edge is then the line's. Returns false when the
  // star has more than kMaxStar faces, or Vd has no other feature edge.
  bool Build(const Ring& fan, int target, const Ring& target_fan, int line_other = -1);
  bool Contains(const DVec3& q) const {
    return q.x >= lo.x && q.y >= lo.y && q.z >= lo.z && q.x <= hi.x && q.y <= hi.y && q.z <= hi.z;
  }
  int extra_faces() const { return count - fan_faces; }
  // The mean of the link's vertices (the surviving faces' edges b - c run once round the link).
  DVec3 LinkCentre() const {
    DVec3 sum{0, 0, 0};
    int n = 0;
    for (int k = 0; k < count; ++k)
      if (survives[k]) {
        sum += b[k];
        ++n;
      }
    return n > 0 ? (1.0 / n) * sum : 0.5 * (v + vd);
  }
};

// Where P is best: the point that minimises the squared distances to the old faces' planes
// (area-weighted: the quadric of the old patch), kept on the plane that leaves the volume under
// the star unchanged, with a small pull towards the edge's midpoint that decides where the
// quadric alone does not (a flat or cylindrical patch). Falls back to the midpoint when the
// system is singular.
DVec3 OptimalPosition(const EdgeStar& star);

// p moved along the star's area normal onto the plane of the points that leave the volume under
// the star unchanged (p itself where that plane is undefined: a flat star folded shut).
DVec3 OntoVolumePlane(const EdgeStar& star, const DVec3& p);

}  // namespace femsimp
