// The thread-safe half-edge collapse of the paper (Listing 1 / Listing 2), written once against
// a memory port (port.h) so the native and the cell back ends run the very same code.
//
// Locking. A context locks V and then every vertex of V's one-ring (status word CAS; the lock
// bit sits on top of the state). Every quadword the collapse writes belongs to a face with at
// least two vertices in that locked set (V's fan faces, and the faces across the two deleted
// link edges), and a triangle cannot hold two vertices of each of two disjoint locked sets, so
// no two contexts ever write the same quadword, and everything the collapse reads is stable
// once the locks are held. (The paper locks V only and checks that the neighbours are not
// locked; two non-adjacent vertices sharing an edge of their link could then rewrite the same
// twin pointers at once, which the one-ring lock rules out.)
//
// Stale reads. On the cell back end reads come from a non-coherent software cache. A
// neighbourhood only changes by collapsing one of its vertices, and that vertex is then marked
// removed in the coherent status words; so a stale view shows up as a ring that does not
// close, a face marked removed, or a removed vertex in a ring. The kernel then asks the port to
// Refresh (dirty the cached lines) and re-reads once, or gives the candidate up.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "engine/criteria.h"
#include "engine/deviation.h"
#include "engine/features.h"
#include "engine/fidelity.h"
#include "engine/quadric.h"
#include "engine/ring.h"
#include "engine/simplify.h"

namespace femsimp {

struct KernelStats {
  uint64_t tried = 0, removed = 0, lock_conflicts = 0, inconsistent = 0;
  uint64_t stale_reread = 0;
  std::array<uint64_t, static_cast<int>(Reject::kCount)> rejections{};
};

// Shared by all contexts of a pass: the vertex count may not drop below the target.
struct RemovalBudget {
  std::atomic<int64_t> alive{0};
  int64_t target = 0;  // 0: no target
  std::atomic<bool> stop{false};

  bool Reserve() {
    if (target <= 0) return true;
    if (alive.fetch_sub(1, std::memory_order_relaxed) <= target) {
      alive.fetch_add(1, std::memory_order_relaxed);
      stop.store(true, std::memory_order_relaxed);
      return false;
    }
    return true;
  }
  void Unreserve() {  // a reserved removal did not happen after all
    if (target > 0) alive.fetch_add(1, std::memory_order_relaxed);
  }
  void Removed() {
    if (target <= 0) alive.fetch_sub(1, std::memory_order_relaxed);
  }
};

inline constexpr uint32_t kGeometryCyclesPerFace = 30;

enum class Outcome { kRemoved, kRejected, kConflict, kInconsistent, kSkipped, kBudgetSpent };

template <class Port>
class RemovalKernel {
 public:
  RemovalKernel(Port& port, const CriteriaSet& criteria, const FidelityConfig& fidelity,
                RemovalBudget& budget, KernelStats& stats)
      : port_(port), criteria_(criteria), fidelity_(fidelity), budget_(budget), stats_(stats) {}

  Outcome TryRemove(uint32_t v) {
    ++stats_.tried;
    port_.BeginCandidate();
    if (!port_.CasStatus(v, kRemovable, kRemovable | kLockedBit)) {
      const uint32_t s = port_.LoadStatus(v);
      if (s & kLockedBit) return Count(Outcome::kConflict);
      return Outcome::kSkipped;  // no longer removable (changed since the sort)
    }
    nlocked_ = 0;
    for (int attempt = 0;; ++attempt) {
      const RingResult r = GatherRing(port_, v, ring_);
      if (r == RingResult::kTooWide) return MarkNotRemovable(v, Reject::kValence);
      LockResult locked = LockResult::kStale;
      if (r == RingResult::kOk) locked = LockNeighbours();
      if (locked == LockResult::kHeld) break;
      if (locked == LockResult::kConflict) {
        port_.StoreStatus(v, kRemovable);
        return Count(Outcome::kConflict);
      }
      if (attempt == 0 && port_.Refresh()) {
        ++stats_.stale_reread;
        continue;
      }
      port_.StoreStatus(v, kRemovable);
      return Count(Outcome::kInconsistent);
    }
    return Collapse(v);
  }

 private:
  Outcome Count(Outcome o) {
    if (o == Outcome::kConflict) ++stats_.lock_conflicts;
    if (o == Outcome::kInconsistent) ++stats_.inconsistent;
    return o;
  }

  enum class LockResult { kHeld, kConflict, kStale };

  // Locks every neighbour of V: kConflict if another context holds one, kStale if one is
  // already removed (the ring came from stale data). On failure nothing stays locked but V.
  LockResult LockNeighbours() {
    const int n = ring_.neighbours();
    for (int i = 0; i < n; ++i) {
      const uint32_t u = ring_.nbr[i];
      const uint32_t s = port_.LoadStatus(u);
      LockResult fail = LockResult::kHeld;
      if (s & kLockedBit) {
        fail = LockResult::kConflict;
      } else if ((s & kStateMask) == kRemoved) {
        fail = LockResult::kStale;
      } else if (!port_.CasStatus(u, s, s | kLockedBit)) {
        fail = LockResult::kConflict;
      }
      if (fail != LockResult::kHeld) {
        UnlockNeighbours();
        return fail;
      }
      locked_[nlocked_] = u;
      locked_state_[nlocked_++] = s;
    }
    return LockResult::kHeld;
  }

  void UnlockNeighbours() {
    for (int i = 0; i < nlocked_; ++i) port_.StoreStatus(locked_[i], locked_state_[i]);
    nlocked_ = 0;
  }

  Outcome MarkNotRemovable(uint32_t v, Reject why) {
    ++stats_.rejections[static_cast<int>(why)];
    UnlockNeighbours();
    port_.StoreStatus(v, kNotRemovable);
    return Outcome::kRejected;
  }

  // Directions a vertex may collapse along: any neighbour of a free vertex; only the two line
  // neighbours of a vertex on a feature line (a boundary is one); none for a corner.
  Outcome Collapse(uint32_t v) {
    const int n = ring_.neighbours();
    int line[2] = {-1, -1}, features = 0;
    for (int i = 0; i < n; ++i)
      if (ring_.feature[i]) {
        if (features < 2) line[features] = i;
        ++features;
      }
    if ((features != 0 && features != 2) || (features == 0 && ring_.boundary) ||
        (features == 2 && TurnsSharply(ring_.pos[line[0]], ring_.center_pos, ring_.pos[line[1]],
                                       fidelity_.cos_feature))) {
      ++stats_.rejections[static_cast<int>(Reject::kFeature)];
      UnlockNeighbours();
      port_.StoreStatus(v, kFixed);
      return Outcome::kRejected;
    }
    if (fidelity_.quadric) own_quadric_ = port_.ReadQuadric(v);
    attrs_loaded_ = false;
    int order[kMaxRing + 1];
    double score[kMaxRing + 1];
    int passing = 0;
    Reject furthest = Reject::kDegenerate;
    bool any_geometric_pass = false;
    for (int i = 0; i < n; ++i) {
      if (features == 2 && i != line[0] && i != line[1]) continue;
      geometry_.Build(ring_, i);
      // Two cross products per triangle, then the criteria (the topology-only mode runs fewer).
      port_.ChargeCompute((kGeometryCyclesPerFace + criteria_.CyclesPerFace()) * geometry_.faces);
      Reject failed;
      if (!criteria_.Accept(geometry_, &failed)) {
        if (static_cast<int>(failed) > static_cast<int>(furthest)) furthest = failed;
        continue;
      }
      any_geometric_pass = true;
      // Insertion by score: the direction that bends the surface least (or, with the quadric
      // cost, adds the least quadric error) is tried first.
      const double s = fidelity_.quadric ? -QuadricError(own_quadric_, ToD(ring_.pos[i]))
                                         : geometry_.MinNormalCosine();
      int k = passing++;
      while (k > 0 && score[k - 1] < s) {
        score[k] = score[k - 1];
        order[k] = order[k - 1];
        --k;
      }
      score[k] = s;
      order[k] = i;
    }
    Reject topo_reason = Reject::kLink;
    Reject late_reason = Reject::kCount;  // a direction passed topology but not fidelity
    for (int k = 0; k < passing; ++k) {
      const int i = order[k];
      const TopologyResult t = CheckTopology(i);
      if (t == TopologyResult::kStale) {
        UnlockNeighbours();
        port_.StoreStatus(v, kRemovable);
        return Count(Outcome::kInconsistent);
      }
      if (t == TopologyResult::kValence) topo_reason = Reject::kValence;
      if (t != TopologyResult::kOk) continue;
      const int line_other = features == 2 ? (i == line[0] ? line[1] : line[0]) : -1;
      if (line_other >= 0 && VdHasFeatureEdgeTo(ring_.nbr[line_other])) {
        late_reason = Reject::kFeature;  // the line would fold onto an existing feature edge
        continue;
      }
      if (Reject r = PrepareFidelity(i, line_other); r != Reject::kCount) {
        late_reason = r;
        continue;
      }
      if (!budget_.Reserve()) {
        UnlockNeighbours();
        port_.StoreStatus(v, kRemovable);
        return Outcome::kBudgetSpent;
      }
      if (fidelity_.ledger != nullptr && (delta_.entries > 0 || fidelity_.ledger->tracks_mass())) {
        if (Reject r = fidelity_.ledger->TryCommit(delta_); r != Reject::kCount) {
          budget_.Unreserve();
          late_reason = r;
          continue;
        }
      }
      Apply(i);
      WriteFidelity(i);
      budget_.Removed();
      port_.StoreStatus(v, kRemoved);
      UnlockNeighbours();
      ++stats_.removed;
      return Outcome::kRemoved;
    }
    if (late_reason != Reject::kCount) return MarkNotRemovable(v, late_reason);
    return MarkNotRemovable(v, any_geometric_pass ? topo_reason : furthest);
  }

  // True when Vd's fan (gathered by CheckTopology) has a feature edge to w.
  bool VdHasFeatureEdgeTo(uint32_t w) const {
    for (int a = 0; a < other_.neighbours(); ++a)
      if (other_.nbr[a] == w && other_.feature[a]) return true;
    return false;
  }

  // The deviation bound, new field values and budget delta of collapsing onto nbr[i]; returns
  // the criterion that refuses it, or kCount.
  Reject PrepareFidelity(int i, int line_other) {
    const int nf = ring_.faces;
    if (fidelity_.reads_attrs() && !attrs_loaded_) {
      for (int f = 0; f < nf; ++f) fan_attr_[f] = port_.ReadFaceAttr(FaceOf(ring_.out[f]));
      attrs_loaded_ = true;
    }
    if (fidelity_.reads_attrs())
      for (int f = 0; f < nf; ++f) new_attr_[f] = fan_attr_[f];
    delta_ = CollapseDelta{};
    if (fidelity_.tracks_error()) {
      float old_error[kMaxRing], new_error[kMaxRing];
      for (int f = 0; f < nf; ++f) old_error[f] = fan_attr_[f].error;
      int work = 0;
      const bool bounded = BoundDeviation(ring_, i, line_other, old_error, new_error, &work);
      port_.ChargeCompute(static_cast<uint32_t>(24 * work));
      if (!bounded) return Reject::kTolerance;
      const int n = ring_.neighbours();
      for (int f = 0; f < nf; ++f) {
        if (f == i || (f + 1) % n == i) continue;  // deleted
        if (new_error[f] > fidelity_.tolerance) return Reject::kTolerance;
        new_attr_[f].error = new_error[f];
      }
    }
    if (fidelity_.ledger != nullptr && fidelity_.ledger->tracks_mass()) {
      CollapseMassDelta(ring_, i, fidelity_.closed, &delta_);
      port_.ChargeCompute(40 * nf);
    }
    if (fidelity_.fields > 0) {
      int slot[kMaxRing];
      for (int f = 0; f < nf; ++f) slot[f] = fidelity_.groups->Of(ring_.group[f]);
      FaceAttrQ transferred[kMaxRing];
      TransferFields(ring_, i, fidelity_.fields, new_attr_, slot, transferred, &delta_);
      for (int f = 0; f < nf; ++f) new_attr_[f] = transferred[f];
      port_.ChargeCompute(60 * nf * fidelity_.fields);
    }
    return Reject::kCount;
  }

  // After Apply: the surviving fan faces' side quadwords, and Vd absorbs V's quadric.
  void WriteFidelity(int i) {
    const int n = ring_.neighbours();
    if (fidelity_.reads_attrs())
      for (int f = 0; f < ring_.faces; ++f)
        if (f != i && (f + 1) % n != i) port_.WriteFaceAttr(FaceOf(ring_.out[f]), new_attr_[f]);
    if (fidelity_.quadric) {
      QuadricQ q = port_.ReadQuadric(ring_.nbr[i]);
      AddQuadric(q, own_quadric_);
      port_.WriteQuadric(ring_.nbr[i], q);
    }
  }

  enum class TopologyResult { kOk, kLink, kValence, kStale };

  // Faces of V's fan that contain the edge V-Vd, and the vertex opposite that edge in each.
  struct Deleted {
    int count = 0;
    int face[2];        // fan face index
    bool vd_second[2];  // fan face is (V, Vd, u) rather than (V, u, Vd)
    uint32_t opposite[2];
  };

  Deleted DeletedFaces(int i) const {
    Deleted d;
    const int n = ring_.neighbours();
    if (i < ring_.faces) {  // face i = (V, Vd, nbr[i + 1])
      d.face[d.count] = i;
      d.vd_second[d.count] = true;
      d.opposite[d.count++] = ring_.nbr[(i + 1) % n];
    }
    if (!ring_.boundary || i > 0) {  // face i - 1 = (V, nbr[i - 1], Vd)
      const int j = (i - 1 + ring_.faces) % ring_.faces;
      d.face[d.count] = j;
      d.vd_second[d.count] = false;
      d.opposite[d.count++] = ring_.nbr[j];
    }
    return d;
  }

  // Link condition (no edge between vertices that are already connected, so no duplicate
  // face, no pinched vertex, no change of genus) and the valence of the opposite vertices
  // (a closed component never shrinks below a tetrahedron, an open one never loses its last
  // face). Reads Vd's fan, which the locks keep stable; on a stale view returns kStale.
  TopologyResult CheckTopology(int i) {
    const uint32_t vd = ring_.nbr[i];
    const Deleted del = DeletedFaces(i);
    const RingResult ring = GatherRing(port_, vd, other_);
    if (ring == RingResult::kTooWide) return TopologyResult::kValence;
    if (ring != RingResult::kOk) return Stale();
    bool sees_v = false;
    for (int a = 0; a < other_.neighbours(); ++a) {
      const uint32_t w = other_.nbr[a];
      if (w == ring_.center) {
        sees_v = true;
        continue;
      }
      if ((port_.LoadStatus(w) & kStateMask) == kRemoved) return Stale();
      if (w == del.opposite[0] || (del.count == 2 && w == del.opposite[1])) continue;
      for (int b = 0; b < ring_.neighbours(); ++b)
        if (ring_.nbr[b] == w) return TopologyResult::kLink;
    }
    if (!sees_v) return Stale();
    for (int k = 0; k < del.count; ++k) {
      int faces = 0;
      bool boundary = false;
      if (!CountFan(del.opposite[k], 4, &faces, &boundary)) return Stale();
      if (faces < (boundary ? 2 : 4)) return TopologyResult::kValence;
    }
    return TopologyResult::kOk;
  }

  TopologyResult Stale() {
    port_.Refresh();  // so the next candidate does not trip over the same stale lines
    return TopologyResult::kStale;
  }

  // Counts the fan of u up to `limit` faces, with the same consistency checks as GatherRing.
  bool CountFan(uint32_t u, int limit, int* faces, bool* boundary) {
    const uint32_t start = port_.ReadVertex(u).out;
    if (start == kNone) return false;
    uint32_t h = start;
    *faces = 0;
    *boundary = false;
    while (*faces < limit) {
      const HalfEdgeQ e0 = port_.ReadHalfEdge(h);
      const HalfEdgeQ e2 = port_.ReadHalfEdge(Prev(h));
      if (((e0.flags | e2.flags) & kFaceRemoved) || e2.target != u) return false;
      if ((port_.LoadStatus(e0.target) & kStateMask) == kRemoved) return false;
      ++*faces;
      if (e2.twin == kNone) {
        *boundary = true;
        return port_.ReadHalfEdge(start).twin == kNone;
      }
      h = e2.twin;
      if (h == start) return true;
    }
    return true;
  }

  // Collapses V onto ring_.nbr[i]. Order as in the paper: faces marked removed, twins across
  // the deleted faces joined, outgoing half-edges of the survivors repaired, and the pointers
  // to V redirected last, so that a concurrent reader sees V's neighbourhood as inconsistent
  // (never as a valid but wrong one) until the update is complete.
  void Apply(int i) {
    const uint32_t vd = ring_.nbr[i];
    const Deleted del = DeletedFaces(i);
    const int nf = ring_.faces;
    uint32_t pair_v[2], pair_vd[2];  // per deleted face: twins of its two edges other than V-Vd
    for (int k = 0; k < del.count; ++k) {
      const int f = del.face[k];
      const uint32_t h = ring_.out[f];
      // (V, Vd, u): edges u-V (prev h) and Vd-u (next h). (V, u, Vd): V-u (h) and u-Vd (next h).
      pair_v[k] = del.vd_second[k] ? FanTwinOfPrev(f) : FanTwinOfOut(f);
      pair_vd[k] = port_.ReadHalfEdgeFresh(Next(h)).twin;
    }
    for (int k = 0; k < del.count; ++k) {
      const uint32_t h0 = 3 * FaceOf(ring_.out[del.face[k]]);
      for (uint32_t e = h0; e < h0 + 3; ++e) port_.WriteFlags(e, kFaceRemoved);
    }
    for (int k = 0; k < del.count; ++k) {
      if (pair_v[k] != kNone) port_.WriteTwin(pair_v[k], pair_vd[k]);
      if (pair_vd[k] != kNone) port_.WriteTwin(pair_vd[k], pair_v[k]);
      JoinFeatureBits(pair_v[k], pair_vd[k]);
    }
    // Outgoing half-edges. For each deleted face the pair member that leaves a vertex is known
    // from the face's orientation; if it does not exist, the next of the other member does.
    for (int k = 0; k < del.count; ++k) {
      const uint32_t u = del.opposite[k];
      const uint32_t from_u = del.vd_second[k] ? pair_vd[k] : pair_v[k];
      const uint32_t into_u = del.vd_second[k] ? pair_v[k] : pair_vd[k];
      RepairOut(u, from_u, into_u, del);
    }
    {
      const int k = del.vd_second[0] ? 0 : del.count - 1;
      const uint32_t from_vd = del.vd_second[k] ? pair_v[k] : pair_vd[k];
      const uint32_t into_vd = del.vd_second[k] ? pair_vd[k] : pair_v[k];
      RepairOut(vd, from_vd, into_vd, del);
    }
    for (int f = 0; f < nf; ++f) {
      if (f == del.face[0] || (del.count == 2 && f == del.face[1])) continue;
      port_.WriteTarget(Prev(ring_.out[f]), vd);
    }
    port_.ChargeCompute(40 * nf);
  }

  // The two edges joined across a deleted face become one: a feature if either was.
  void JoinFeatureBits(uint32_t a, uint32_t b) {
    if (a == kNone || b == kNone) return;
    const uint32_t fa = port_.ReadHalfEdgeFresh(a).flags, fb = port_.ReadHalfEdgeFresh(b).flags;
    if (((fa ^ fb) & kFeatureEdge) == 0) return;
    port_.WriteFlags(a, fa | kFeatureEdge);
    port_.WriteFlags(b, fb | kFeatureEdge);
  }

  // Twin of out[f] (V -> nbr[f]) and of prev(out[f]) (nbr[f+1] -> V), known from the fan walk.
  uint32_t FanTwinOfOut(int f) const {
    if (f == 0 && ring_.boundary) return kNone;
    return Prev(ring_.out[(f - 1 + ring_.faces) % ring_.faces]);
  }
  uint32_t FanTwinOfPrev(int f) const {
    if (f == ring_.faces - 1 && ring_.boundary) return kNone;
    return ring_.out[(f + 1) % ring_.faces];
  }

  // Gives w a valid outgoing half-edge if its own lay in a deleted face; on a boundary vertex
  // it must be the clockwise-most one (the one without twin), found by rotating clockwise over
  // the already joined twins. Reads bypass any cache: w is locked, so memory is current.
  void RepairOut(uint32_t w, uint32_t from_w, uint32_t into_w, const Deleted& del) {
    const uint32_t face = FaceOf(port_.ReadVertexFresh(w).out);
    bool deleted = false;
    for (int k = 0; k < del.count; ++k) deleted |= face == FaceOf(ring_.out[del.face[k]]);
    if (!deleted) return;
    if (from_w == kNone && into_w == kNone) return;  // ruled out by the valence check
    uint32_t g = from_w != kNone ? from_w : Next(into_w);
    const uint32_t start = g;
    for (int steps = 0; steps < 4 * kMaxRing; ++steps) {
      const uint32_t t = port_.ReadHalfEdgeFresh(g).twin;
      if (t == kNone) break;
      const uint32_t cw = Next(t);
      if (cw == start) break;
      g = cw;
    }
    port_.WriteOut(w, g);
  }

  Port& port_;
  const CriteriaSet& criteria_;
  const FidelityConfig& fidelity_;
  RemovalBudget& budget_;
  KernelStats& stats_;
  Ring ring_, other_;
  CollapseGeometry geometry_;
  QuadricQ own_quadric_{};
  bool attrs_loaded_ = false;
  FaceAttrQ fan_attr_[kMaxRing];  // the fan faces' side quadwords, read once per candidate
  FaceAttrQ new_attr_[kMaxRing];  // their values after the collapse being prepared
  CollapseDelta delta_;
  uint32_t locked_[kMaxRing + 1];
  uint32_t locked_state_[kMaxRing + 1];
  int nlocked_ = 0;
};

}  // namespace femsimp
