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
#include <memory>

#include <optional>
#include <span>

#include "engine/quadric.h"
#include "engine/ring.h"
#include "engine/rule.h"
#include "engine/simplify.h"
#include "engine/star.h"

namespace femsimp {

struct KernelStats {
  uint64_t tried = 0, removed = 0, lock_conflicts = 0, inconsistent = 0;
  uint64_t placed = 0;           // of the removals: full-edge collapses (option placement)
  uint64_t placed_on_lines = 0;  // of those: V and Vd on one feature line
  uint64_t stale_reread = 0;
  std::array<uint64_t, static_cast<int>(Reject::kCount)> rejections{};
  // Refused vertices this context made removable again (their fans changed): the next
  // selection's candidates besides the pass's own (engine/selection.h). Duplicates allowed.
  std::vector<uint32_t> requeued;
  // With record_changed (the rounds ask for it): vertices whose one-ring this context's commits
  // changed (every vertex a commit locked: V's neighbours, and with placement Vd's); the rounds
  // keep the boxes of the others (engine/rounds.h). Duplicates allowed.
  bool record_changed = false;
  std::vector<uint32_t> changed;
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

// One candidate, in named steps: lock V → read and lock its fan → the directions it may take →
// rank them → for each in rank order: the rules on V's fan (shape, the fidelity screen),
// topology rules, fidelity rules → reserve a removal → spend the budgets → commit → unlock. The
// rules are units (engine/rule.h); the kernel owns the locking, the reads through the port and
// the update of the mesh.
template <class Port>
class RemovalKernel final : private NeighbourhoodReader {
 public:
  // quadric: the quadric cost is on (directions ranked by it, Vd absorbs V's quadric).
  // placement: try a full-edge collapse where V and Vd may both move (engine/star.h), when every
  // rule of the run judges them (on a feature line only when a rule holds moved lines).
  // requeue_changed: a commit makes the refused vertices among the ones it locked (their fans
  // changed) removable again.
  RemovalKernel(Port& port, const RuleSet& rules, bool quadric, RemovalBudget& budget,
                KernelStats& stats, bool placement = false, bool requeue_changed = false)
      : port_(port),
        rules_(rules),
        quadric_(quadric),
        placement_(placement && rules.judges_placement()),
        requeue_changed_(requeue_changed),
        budget_(budget),
        stats_(stats) {
    if (placement_) placing_ = std::make_unique<Placing>();
    // Serials unique across kernels: a later kernel may get an earlier one's address.
    static std::atomic<uint64_t> kernels{0};
    proposal_.fan_serial = kernels.fetch_add(1, std::memory_order_relaxed) << 32;
  }

  Outcome TryRemove(uint32_t v) {
    ++stats_.tried;
    port_.BeginCandidate();
    if (!port_.CasStatus(v, kRemovable, kRemovable | kLockedBit)) {
      const uint32_t s = port_.LoadStatus(v);
      if (s & kLockedBit) return Count(Outcome::kConflict);
      return Outcome::kSkipped;  // no longer removable (changed since the sort)
    }
    if (std::optional<Outcome> failed = ReadAndLockFan(v)) return *failed;
    const Directions directions = AllowedDirections(ring_);
    if (directions.fixed) return Fix(v);
    refusal_ = Refusal{};
    screen_first_ = false;
    // A full-edge collapse moves V off its place: where V is on no line, or (when a rule holds
    // moved lines) along its line onto a neighbour on the same line, never on a boundary.
    const bool v_free =
        placement_ && !ring_.boundary && (!directions.on_line() || rules_.places_on_lines());
    const int ranked = RankDirections(directions);
    for (int k = 0; k < ranked; ++k) {
      const int i = order_[k];
      proposal_.line_other = directions.LineOther(i);
      if (CheckFan(i) != Verdict::kPass) continue;
      const Verdict topology = CheckTopology(i);
      if (topology == Verdict::kStale) return GiveUp(v, Outcome::kInconsistent);
      if (topology == Verdict::kReject) continue;
      const Verdict fidelity = CheckFidelity();
      if (fidelity == Verdict::kConflict) return GiveUp(v, Outcome::kConflict);
      if (fidelity != Verdict::kPass) {
        if (v_free && fidelity == Verdict::kReject && rules_.placement_may_pass(fidelity_refused_))
          if (std::optional<Outcome> placed = TryPlaced(v, i)) return *placed;
        continue;
      }
      if (!budget_.Reserve()) return GiveUp(v, Outcome::kBudgetSpent);
      Reject refused = Reject::kCount;
      if (rules_.SpendBudgets(ring_.center, proposal_.delta, &refused)) {
        Commit(v, i);
        return Outcome::kRemoved;
      }
      budget_.Unreserve();
      Note(RuleStage::kBudget, refused);
      // A mass budget refuses the half-edge collapse: V and Vd merged where the volume stays
      // may pass. Only then, or where the refusing fidelity rule says a placed vertex may pass
      // it (above): off the input surface a vertex spends more of a deviation bound that adds
      // up than a half-edge collapse, which keeps it on (docs/FIDELITY.md § 11).
      if (v_free)
        if (std::optional<Outcome> placed = TryPlaced(v, i)) return *placed;
    }
    return MarkNotRemovable(v, refusal_.reason, refusal_.beyond_fan);
  }

  // Compound collapses (engine/seam_collapse.h), run by one context alone: checks V -> vd with
  // every rule but the budgets, whatever V's state (a seam copy is kFixed), and on kPass keeps V
  // and its one-ring locked and the proposal ready until CommitHeld or ReleaseHeld.
  // `also_replaced`: faces of the compound's other collapses, which the intersection check
  // leaves to the compound's own test (they are rewritten too). *refused names a refusal.
  Verdict HoldCollapse(uint32_t v, uint32_t vd, std::span<const uint32_t> also_replaced,
                       Reject* refused) {
    const uint32_t state = port_.LoadStatus(v);
    if ((state & kLockedBit) || (state & kStateMask) == kRemoved) return Verdict::kConflict;
    if (!port_.CasStatus(v, state, state | kLockedBit)) return Verdict::kConflict;
    held_v_ = v;
    held_state_ = state;
    nlocked_ = 0;
    proposal_.also_replaced = also_replaced;
    if (GatherRing(port_, v, ring_) != RingResult::kOk) return FailHold(Verdict::kStale);
    if (LockNeighbours() != LockResult::kHeld) return FailHold(Verdict::kConflict);
    proposal_.fan = &ring_;
    ++proposal_.fan_serial;
    proposal_.fan_smallest_angle_cos2 = -1.0;
    proposal_.reader = this;
    proposal_.star = nullptr;
    refusal_ = Refusal{};
    const Directions directions = AllowedDirections(ring_);
    int i = 0;
    while (i < ring_.neighbours() && ring_.nbr[i] != vd) ++i;
    if (directions.fixed || i == ring_.neighbours() || !directions.Allows(i)) {
      *refused = Reject::kFeature;
      return FailHold(Verdict::kReject);
    }
    if (quadric_) own_quadric_ = port_.ReadQuadric(ring_.center);
    attrs_loaded_ = false;
    proposal_.line_other = directions.LineOther(i);
    Verdict verdict = CheckShape(i);
    if (verdict == Verdict::kPass) verdict = CheckScreen();
    if (verdict == Verdict::kPass) verdict = CheckTopology(i);
    if (verdict == Verdict::kPass) verdict = CheckFidelity();
    if (verdict != Verdict::kPass) {
      *refused = refusal_.reason;
      return FailHold(verdict);
    }
    held_i_ = i;
    return Verdict::kPass;
  }
  const CollapseProposal& held() const { return proposal_; }
  void CommitHeld() { Commit(held_v_, held_i_); }
  void ReleaseHeld() {
    UnlockNeighbours();
    port_.StoreStatus(held_v_, held_state_);
  }

 private:
  Verdict FailHold(Verdict v) {
    ReleaseHeld();
    return v;
  }

  // The kDirections rules on a fan (V's, or Vd's for a full-edge collapse).
  Directions AllowedDirections(const Ring& fan) const {
    Directions directions;
    for (const CollapseRule* rule : rules_.stage(RuleStage::kDirections))
      rule->Restrict(fan, &directions);
    return directions;
  }

  // Proposes the direction V -> nbr[i] and runs the shape rules on its new triangles.
  Verdict CheckShape(int i) {
    proposal_.target = i;
    proposal_.geometry.Build(ring_, i);
    // Two cross products per triangle, then the rules (the topology-only mode runs fewer).
    port_.ChargeCompute((kGeometryCyclesPerFace + rules_.shape_cycles_per_face()) *
                        proposal_.geometry.faces);
    Reject refused = Reject::kCount;
    const Verdict v = rules_.Check(RuleStage::kShape, proposal_, &refused);
    if (v != Verdict::kPass) Note(RuleStage::kShape, refused);
    return v;
  }

  // The rules on V's fan alone for the direction V -> nbr[i]: the shape rules (which the
  // ranking ran already unless the quadric cost ranks) and the fidelity rules' screen. A
  // direction must pass both, so their order changes no verdict, only the work: the screen
  // goes first once it has refused a direction the shape rules passed (where the tolerance
  // holds V, it mostly holds every direction).
  Verdict CheckFan(int i) {
    proposal_.target = i;
    if (!quadric_) return CheckScreen();
    if (screen_first_) {
      const Verdict screen = CheckScreen();
      return screen == Verdict::kPass ? CheckShape(i) : screen;
    }
    const Verdict shape = CheckShape(i);
    if (shape != Verdict::kPass) return shape;
    const Verdict screen = CheckScreen();
    screen_first_ = screen == Verdict::kReject;
    return screen;
  }

  // The fidelity rules' early tests on V's fan (RuleStage::kScreen), before Vd's ring is read.
  Verdict CheckScreen() {
    if (rules_.stage(RuleStage::kScreen).empty()) return Verdict::kPass;
    if (rules_.reads_face_attrs()) LoadFanAttrs();
    proposal_.cycles = 0;
    Reject refused = Reject::kCount;
    const Verdict v = rules_.Check(RuleStage::kScreen, proposal_, &refused);
    port_.ChargeCompute(proposal_.cycles);
    if (v == Verdict::kReject) Note(RuleStage::kFidelity, refused);
    return v;
  }

  Outcome Count(Outcome o) {
    if (o == Outcome::kConflict) ++stats_.lock_conflicts;
    if (o == Outcome::kInconsistent) ++stats_.inconsistent;
    return o;
  }

  enum class LockResult { kHeld, kConflict, kStale };

  // Gathers V's fan and locks every neighbour; on a stale view asks the port to refresh and
  // tries once more. On failure V is unlocked again and the outcome returned.
  std::optional<Outcome> ReadAndLockFan(uint32_t v) {
    nlocked_ = 0;
    for (int attempt = 0;; ++attempt) {
      const RingResult r = GatherRing(port_, v, ring_);
      if (r == RingResult::kTooWide) return MarkNotRemovable(v, Reject::kValence, false);
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
    proposal_.fan = &ring_;
    proposal_.fan_smallest_angle_cos2 = -1.0;
    proposal_.reader = this;
    proposal_.star = nullptr;
    if (placement_) RefreshPositions(ring_);
    ++proposal_.fan_serial;
    return std::nullopt;
  }

  // Locks every neighbour of V: kConflict if another context holds one, kStale if one is
  // already removed (the ring came from stale data). On failure nothing stays locked but V.
  LockResult LockNeighbours() {
    const int n = ring_.neighbours();
    for (int i = 0; i < n; ++i) {
      if (const LockResult r = LockOne(ring_.nbr[i]); r != LockResult::kHeld) {
        UnlockNeighbours();
        return r;
      }
    }
    return LockResult::kHeld;
  }

  LockResult LockOne(uint32_t u) {
    const uint32_t s = port_.LoadStatus(u);
    if (s & kLockedBit) return LockResult::kConflict;
    if ((s & kStateMask) == kRemoved) return LockResult::kStale;
    if (!port_.CasStatus(u, s, s | kLockedBit)) return LockResult::kConflict;
    locked_[nlocked_] = u;
    locked_state_[nlocked_++] = s;
    return LockResult::kHeld;
  }

  // A full-edge collapse also locks the rest of Vd's one-ring: the star's outer corners, which
  // no other full-edge collapse may move meanwhile. On failure only those are unlocked again.
  LockResult LockRestOf(const Ring& fan) {
    const int base = nlocked_;
    for (int a = 0; a < fan.neighbours(); ++a) {
      const uint32_t u = fan.nbr[a];
      if (u == ring_.center || std::find(locked_, locked_ + nlocked_, u) != locked_ + nlocked_)
        continue;
      if (const LockResult r = LockOne(u); r != LockResult::kHeld) {
        UnlockFrom(base);
        return r;
      }
    }
    return LockResult::kHeld;
  }
  void UnlockFrom(int base) {
    for (int i = base; i < nlocked_; ++i) port_.StoreStatus(locked_[i], locked_state_[i]);
    nlocked_ = base;
  }

  // Positions move in full-edge collapses; nothing moves a vertex of a fan whose centre this
  // context holds, but the cell port's cache may still have its old place.
  void RefreshPositions(Ring& fan) {
    const VertexQ c = port_.ReadVertexFresh(fan.center);
    fan.center_pos = {c.x, c.y, c.z};
    for (int i = 0; i < fan.neighbours(); ++i) {
      const VertexQ q = port_.ReadVertexFresh(fan.nbr[i]);
      fan.pos[i] = {q.x, q.y, q.z};
    }
  }

  // The full-edge collapse of V and ring_.nbr[i] (its topology already checked), at the first
  // of a few points that passes every rule; nullopt when none does (or Vd may not move), with
  // the extra locks released again.
  std::optional<Outcome> TryPlaced(uint32_t v, int i) {
    refusal_.beyond_fan = true;  // judged on Vd's one-ring too
    if ((locked_state_[i] & kStateMask) == kFixed || other_.boundary) return std::nullopt;
    // Vd moves to P too: off every line, or (V on a line, so V - Vd is one of its edges) on
    // V's line, whose other vertices stay; a line corner stays where it is.
    const Directions vd_directions = AllowedDirections(other_);
    if (vd_directions.fixed || vd_directions.on_line() != (proposal_.line_other >= 0))
      return std::nullopt;
    // A group border stays on its line (the measured check holds surfaces, not groups): only a
    // crease inside one group moves off it.
    if (proposal_.line_other >= 0 &&
        !(InOneGroup(ring_, ring_.group[0]) && InOneGroup(other_, ring_.group[0])))
      return std::nullopt;
    const int base = nlocked_;
    const LockResult locked = LockRestOf(other_);
    if (locked == LockResult::kConflict) return GiveUp(v, Outcome::kConflict);
    if (locked == LockResult::kStale) return GiveUp(v, Outcome::kInconsistent);
    RefreshPositions(other_);
    EdgeStar& star = placing_->star;
    FaceAttrQ* extra_attr = placing_->extra_attr;
    if (!star.Build(ring_, i, other_, proposal_.line_other)) {
      UnlockFrom(base);
      return std::nullopt;
    }
    if (rules_.reads_face_attrs())
      for (int k = 0; k < star.extra_faces(); ++k)
        extra_attr[k] = port_.ReadFaceAttr(star.face[star.fan_faces + k]);
    proposal_.extra_attr = extra_attr;
    proposal_.new_extra_attr = placing_->new_extra_attr;
    // The optimal point; then two more that keep the volume, for when the optimum makes a
    // sliver or crosses another part: the edge's midpoint and the link's centre, each moved onto
    // the plane of the points that keep it; then back along the way from Vd to the optimum
    // (nearer Vd the deviation spent is smaller, nearer the optimum the volume's), and the
    // midpoint itself.
    const DVec3 optimal = OptimalPosition(star);
    const DVec3 towards = optimal - star.vd;
    const DVec3 midpoint = 0.5 * (star.v + star.vd);
    const DVec3 tries[] = {optimal,
                           OntoVolumePlane(star, midpoint),
                           OntoVolumePlane(star, star.LinkCentre()),
                           star.vd + 0.5 * towards,
                           star.vd + 0.25 * towards,
                           midpoint};
    for (const DVec3& at : tries) {
      // Judged where the float it is stored as puts it.
      const Vec3 stored = StoredPosition(at);
      star.p = ToD(stored);
      if (!star.Contains(star.p)) continue;
      proposal_.star = &star;
      proposal_.geometry.Build(star, placing_->apex);
      port_.ChargeCompute((kGeometryCyclesPerFace + rules_.shape_cycles_per_face()) *
                          proposal_.geometry.faces);
      Reject refused = Reject::kCount;
      if (rules_.Check(RuleStage::kShape, proposal_, &refused) != Verdict::kPass) {
        Note(RuleStage::kShape, refused);
        continue;
      }
      const Verdict fidelity = CheckFidelity();
      if (fidelity == Verdict::kConflict) return GiveUp(v, Outcome::kConflict);
      if (fidelity != Verdict::kPass) continue;
      if (!budget_.Reserve()) return GiveUp(v, Outcome::kBudgetSpent);
      if (!rules_.SpendBudgets(ring_.center, proposal_.delta, &refused)) {
        budget_.Unreserve();
        Note(RuleStage::kBudget, refused);
        continue;
      }
      Commit(v, i, &stored);
      return Outcome::kRemoved;
    }
    proposal_.star = nullptr;
    UnlockFrom(base);
    return std::nullopt;
  }

  static bool InOneGroup(const Ring& fan, uint32_t group) {
    for (int f = 0; f < fan.faces; ++f)
      if (fan.group[f] != group) return false;
    return true;
  }

  // Also the end of every candidate that got its fan: the rules give back what they took.
  void UnlockNeighbours() {
    rules_.Release(proposal_);
    for (int i = 0; i < nlocked_; ++i) port_.StoreStatus(locked_[i], locked_state_[i]);
    nlocked_ = 0;
  }

  // The refusal that came furthest (a later stage, or a later rule of the same stage) names
  // why V stays; it is counted once per candidate.
  struct Refusal {
    int rank = -1;
    Reject reason = Reject::kLink;
    bool beyond_fan = false;  // some refusal came from outside V's fan (CollapseRule::fan_local)
  };
  void Note(RuleStage stage, Reject reason) {
    const int rank =
        static_cast<int>(stage) * static_cast<int>(Reject::kCount) + static_cast<int>(reason);
    if (rank >= refusal_.rank) {
      refusal_.rank = rank;
      refusal_.reason = reason;
    }
    if (!rules_.fan_local(reason)) refusal_.beyond_fan = true;
  }

  // beyond_fan: what refused V read more than V's fan, so only reconsideration retries it.
  Outcome MarkNotRemovable(uint32_t v, Reject why, bool beyond_fan) {
    ++stats_.rejections[static_cast<int>(why)];
    UnlockNeighbours();
    port_.StoreStatus(v,
                      requeue_changed_ && beyond_fan ? kNotRemovable | kRetryBit : kNotRemovable);
    return Outcome::kRejected;
  }

  // A corner (or a vertex no rule lets move at all) is never tried again.
  Outcome Fix(uint32_t v) {
    ++stats_.rejections[static_cast<int>(Reject::kFeature)];
    UnlockNeighbours();
    port_.StoreStatus(v, kFixed);
    return Outcome::kRejected;
  }

  // Leaves V removable for a later pass (a stale view, or the vertex target reached).
  Outcome GiveUp(uint32_t v, Outcome o) {
    UnlockNeighbours();
    port_.StoreStatus(v, kRemovable);
    return Count(o);
  }

  // Ranks the allowed directions: the one that bends the surface least (the shape rules run
  // first: its new triangles give the rank) or, with the quadric cost, adds the least quadric
  // error (the shape rules run later, in rank order, only as far as a direction passes every
  // rule). Returns how many are ranked; order_ holds them.
  int RankDirections(const Directions& directions) {
    if (quadric_) own_quadric_ = port_.ReadQuadric(ring_.center);
    attrs_loaded_ = false;
    double score[kMaxRing + 1];
    int passing = 0;
    for (int i = 0; i < ring_.neighbours(); ++i) {
      if (!directions.Allows(i)) continue;
      if (!quadric_ && CheckShape(i) != Verdict::kPass) continue;
      const double s = quadric_ ? -QuadricError(own_quadric_, ToD(ring_.pos[i]))
                                : proposal_.geometry.MinNormalCosine();
      int k = passing++;
      while (k > 0 && score[k - 1] < s) {
        score[k] = score[k - 1];
        order_[k] = order_[k - 1];
        --k;
      }
      score[k] = s;
      order_[k] = i;
    }
    return passing;
  }

  // Reads Vd's fan (which the locks keep stable) and runs the topology rules on it.
  Verdict CheckTopology(int i) {
    const Deleted del = DeletedFaces(i);
    proposal_.deleted = del.count;
    proposal_.opposite[0] = del.opposite[0];
    proposal_.opposite[1] = del.count == 2 ? del.opposite[1] : kNone;
    const RingResult ring = GatherRing(port_, ring_.nbr[i], other_);
    if (ring == RingResult::kTooWide) {
      Note(RuleStage::kTopology, Reject::kValence);
      return Verdict::kReject;
    }
    if (ring != RingResult::kOk) return Stale();
    bool sees_v = false;
    for (int a = 0; a < other_.neighbours(); ++a) {
      const uint32_t w = other_.nbr[a];
      if (w == ring_.center) {
        sees_v = true;
      } else if ((port_.LoadStatus(w) & kStateMask) == kRemoved) {
        return Stale();
      }
    }
    if (!sees_v) return Stale();
    proposal_.target_fan = &other_;
    Reject refused = Reject::kCount;
    const Verdict v = rules_.Check(RuleStage::kTopology, proposal_, &refused);
    if (v == Verdict::kReject) Note(RuleStage::kTopology, refused);
    if (v == Verdict::kStale) return Stale();
    return v;
  }

  Verdict Stale() {
    port_.Refresh();  // so the next candidate does not trip over the same stale lines
    return Verdict::kStale;
  }

  // NeighbourhoodReader: counts the fan of u up to `limit` faces, with the same consistency
  // checks as GatherRing.
  bool CountFan(uint32_t u, int limit, int* faces, bool* boundary) override {
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

  // NeighbourhoodReader: the vertices around u, with CountFan's checks.
  int Neighbours(uint32_t u, uint32_t* out) override {
    const uint32_t start = port_.ReadVertex(u).out;
    if (start == kNone) return -1;
    uint32_t h = start;
    for (int count = 0;;) {
      if (count == kMaxRing) return kMaxRing + 2;
      const HalfEdgeQ e0 = port_.ReadHalfEdge(h);
      const HalfEdgeQ e2 = port_.ReadHalfEdge(Prev(h));
      if (((e0.flags | e2.flags) & kFaceRemoved) || e2.target != u) return -1;
      out[count++] = e0.target;
      if (e2.twin == kNone) {  // a boundary fan: its last face's third corner ends it
        if (port_.ReadHalfEdge(start).twin != kNone) return -1;
        out[count++] = port_.ReadHalfEdge(Next(h)).target;
        return count;
      }
      h = e2.twin;
      if (h == start) return count;
    }
  }

  // The fan faces' side quadwords, read once per candidate.
  void LoadFanAttrs() {
    if (!attrs_loaded_) {
      for (int f = 0; f < ring_.faces; ++f) fan_attr_[f] = port_.ReadFaceAttr(FaceOf(ring_.out[f]));
      attrs_loaded_ = true;
    }
    proposal_.fan_attr = fan_attr_;
  }

  // Runs the fidelity rules: the side quadwords of the fan are read once per candidate, and
  // the rules propose their new values and the collapse's budget delta.
  Verdict CheckFidelity() {
    const int nf = ring_.faces;
    if (rules_.reads_face_attrs()) {
      LoadFanAttrs();
      for (int f = 0; f < nf; ++f) proposal_.new_attr[f] = fan_attr_[f];
      if (proposal_.star != nullptr)
        for (int k = 0; k < proposal_.star->extra_faces(); ++k)
          proposal_.new_extra_attr[k] = placing_->extra_attr[k];
    }
    proposal_.fan_attr = fan_attr_;
    proposal_.delta = CollapseDelta{};
    proposal_.mass_measured = false;
    proposal_.cycles = 0;
    Reject refused = Reject::kCount;
    const Verdict v = rules_.Check(RuleStage::kFidelity, proposal_, &refused);
    port_.ChargeCompute(proposal_.cycles);
    fidelity_refused_ = refused;
    if (v == Verdict::kReject) Note(RuleStage::kFidelity, refused);
    return v;
  }

  // Applies the collapse onto ring_.nbr[i] (a full-edge collapse: and moves it to `placed`),
  // writes the side data the rules proposed, and releases the locks with V removed.
  void Commit(uint32_t v, int i, const Vec3* placed = nullptr) {
    Apply(i);
    if (placed != nullptr) {
      port_.WritePosition(ring_.nbr[i], *placed);
      if (rules_.reads_face_attrs())
        for (int k = 0; k < placing_->star.extra_faces(); ++k)
          port_.WriteFaceAttr(placing_->star.face[placing_->star.fan_faces + k],
                              proposal_.new_extra_attr[k]);
      ++stats_.placed;
      if (proposal_.line_other >= 0) ++stats_.placed_on_lines;
    }
    WriteSideData(i);
    rules_.Commit(proposal_);
    budget_.Removed();
    port_.StoreStatus(v, kRemoved);
    if (stats_.record_changed)
      stats_.changed.insert(stats_.changed.end(), locked_, locked_ + nlocked_);
    // Every locked vertex's fan changed: one refused before may pass now, so it is a
    // candidate again next pass (the local rules refuse an unchanged fan again).
    if (requeue_changed_)
      for (int k = 0; k < nlocked_; ++k)
        if ((locked_state_[k] & kStateMask) == kNotRemovable) {
          locked_state_[k] = kRemovable;
          stats_.requeued.push_back(locked_[k]);
        }
    UnlockNeighbours();
    proposal_.star = nullptr;
    ++stats_.removed;
  }

  // The surviving fan faces' side quadwords, and Vd absorbs V's quadric.
  void WriteSideData(int i) {
    if (rules_.reads_face_attrs())
      for (int f = 0; f < ring_.faces; ++f)
        if (!proposal_.IsDeleted(f))
          port_.WriteFaceAttr(FaceOf(ring_.out[f]), proposal_.new_attr[f]);
    if (quadric_) {
      QuadricQ q = port_.ReadQuadric(ring_.nbr[i]);
      AddQuadric(q, own_quadric_);
      port_.WriteQuadric(ring_.nbr[i], q);
    }
  }

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

  // The two edges joined across a deleted face become one: a feature if either was, and a
  // boundary edge (one side without twin) is a feature whatever it was before.
  void JoinFeatureBits(uint32_t a, uint32_t b) {
    if (a == kNone && b == kNone) return;
    if (a == kNone || b == kNone) {
      const uint32_t e = a == kNone ? b : a;
      const uint32_t f = port_.ReadHalfEdgeFresh(e).flags;
      if (!(f & kFeatureEdge)) port_.WriteFlags(e, f | kFeatureEdge);
      return;
    }
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
  const RuleSet& rules_;
  const bool quadric_;
  const bool placement_;
  const bool requeue_changed_;
  RemovalBudget& budget_;
  KernelStats& stats_;
  Ring ring_, other_;
  CollapseProposal proposal_;
  Refusal refusal_;
  Reject fidelity_refused_ = Reject::kCount;  // the rule that refused the last fidelity check
  int order_[kMaxRing + 1];                   // ranked directions
  bool screen_first_ = false;                 // CheckFan
  QuadricQ own_quadric_{};
  bool attrs_loaded_ = false;
  FaceAttrQ fan_attr_[kMaxRing];  // the fan faces' side quadwords, read once per candidate
  // Full-edge collapses: the star, and the side quadwords of Vd's other faces.
  // On the heap, and only with placement: on the cell back end the kernel lives on an SPE
  // software thread's stack in the local store, which has no room for it.
  struct Placing {
    EdgeStar star;
    FaceAttrQ extra_attr[kMaxRing], new_extra_attr[kMaxRing];
    DVec3 apex[kMaxStar];
  };
  std::unique_ptr<Placing> placing_;

  uint32_t locked_[2 * kMaxRing + 2];  // V's one-ring, then (full-edge) the rest of Vd's
  uint32_t locked_state_[2 * kMaxRing + 2];
  int nlocked_ = 0;
  uint32_t held_v_ = kNone, held_state_ = 0;  // HoldCollapse
  int held_i_ = -1;
};

}  // namespace femsimp
