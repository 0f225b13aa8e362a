// One-ring of a vertex, gathered by walking its fan counter-clockwise, with the consistency
// checks of the paper's Listing 2: every face must close back on the centre, twins must be
// mutual and no face may be marked removed. A failed check means a concurrent or stale view.
#pragma once

#include <cstdint>

#include "engine/quadword.h"

namespace femsimp {

inline constexpr int kMaxRing = 64;  // fans wider than this are left alone (never seen in CAD)

struct Vec3 {
  float x, y, z;
};

struct Ring {
  uint32_t center = kNone;
  Vec3 center_pos{};
  bool boundary = false;
  int faces = 0;               // fan faces, counter-clockwise
  uint32_t out[kMaxRing];      // out[i]: centre -> nbr[i], first half-edge of fan face i
  uint32_t nbr[kMaxRing + 1];  // faces + 1 entries on a boundary (the last closes the fan)
  Vec3 pos[kMaxRing + 1];
  bool feature[kMaxRing + 1];  // the edge centre - nbr[i] is a feature edge
  uint32_t group[kMaxRing];    // face group of fan face i
  uint32_t sides = 0;          // the fan's entry in Mesh::sides() (one sheet: the same for all)
  int neighbours() const { return boundary ? faces + 1 : faces; }
  // Fan face i is (centre, nbr[i], nbr[i + 1]) (indices mod neighbours() when closed).
  uint32_t face_second(int i) const { return nbr[i]; }
  uint32_t face_third(int i) const { return nbr[(i + 1) % (boundary ? faces + 1 : faces)]; }
};

enum class RingResult { kOk, kInconsistent, kTooWide };

template <class Port>
RingResult GatherRing(Port& port, uint32_t center, Ring& ring) {
  const VertexQ cv = port.ReadVertex(center);
  ring.center = center;
  ring.center_pos = {cv.x, cv.y, cv.z};
  ring.faces = 0;
  ring.boundary = false;
  const uint32_t start = cv.out;
  if (start == kNone) return RingResult::kInconsistent;
  uint32_t h = start;
  uint32_t expected_twin = kNone;  // the twin the next fan half-edge must point back to
  bool first = true;
  for (;;) {
    if (ring.faces == kMaxRing) return RingResult::kTooWide;
    const HalfEdgeQ e0 = port.ReadHalfEdge(h);
    const HalfEdgeQ e1 = port.ReadHalfEdge(Next(h));
    const HalfEdgeQ e2 = port.ReadHalfEdge(Prev(h));
    if ((e0.flags | e1.flags | e2.flags) & kFaceRemoved) return RingResult::kInconsistent;
    if (e2.target != center || e0.target == center || e1.target == center)
      return RingResult::kInconsistent;
    if (!first && e0.twin != expected_twin) return RingResult::kInconsistent;
    first = false;
    ring.out[ring.faces] = h;
    ring.nbr[ring.faces] = e0.target;
    ring.feature[ring.faces] = e0.flags & kFeatureEdge;
    ring.group[ring.faces] = e0.group;
    if (ring.faces == 0) ring.sides = e0.flags >> kSidesShift;
    ++ring.faces;
    const uint32_t next_out = e2.twin;
    if (next_out == kNone) {
      // The fan ends on a boundary: it must also have started on one.
      if (port.ReadHalfEdge(start).twin != kNone) return RingResult::kInconsistent;
      ring.boundary = true;
      ring.nbr[ring.faces] = e1.target;
      ring.feature[ring.faces] = e2.flags & kFeatureEdge;
      break;
    }
    if (next_out == start) {
      if (port.ReadHalfEdge(start).twin != Prev(h)) return RingResult::kInconsistent;
      if (e1.target != ring.nbr[0]) return RingResult::kInconsistent;
      break;
    }
    expected_twin = Prev(h);
    h = next_out;
    // A closed fan has consecutive faces sharing an edge: the next face's target is ours.
    if (port.ReadHalfEdge(h).target != e1.target) return RingResult::kInconsistent;
  }
  for (int i = 0; i < ring.neighbours(); ++i) {
    const VertexQ q = port.ReadVertex(ring.nbr[i]);
    ring.pos[i] = {q.x, q.y, q.z};
  }
  return RingResult::kOk;
}

}  // namespace femsimp
