// A rule of the removal kernel: one condition a proposed half-edge collapse V -> Vd must meet.
// Every rule is a type with the same small interface, judged on the collapse's local context
// (CollapseProposal) while the kernel holds the locks of V and its one-ring; the rules of a run
// are listed in engine/rules/rule_list.inc and built from the options (RuleSet::Build).
//
// A rule takes part in one or more stages, which the kernel runs in this order:
//   kDirections  once per candidate: which neighbours V may move to (or none: V is fixed);
//   kShape       per allowed direction, on the geometry of the new triangles; the directions
//                that pass are ranked and the rest of the stages run in rank order;
//   kScreen      a fidelity rule's cheap early test on V's fan alone, refusing only what its
//                kFidelity check would (so that a direction refused anyway costs no read of
//                Vd's ring); its refusals count as fidelity refusals;
//   kTopology    on Vd's one-ring (and, through NeighbourhoodReader, a little beyond);
//   kFidelity    on the side data (deviation bounds, fields): proposes the new side quadwords
//                and the collapse's change of the global budgets (CollapseProposal::delta);
//   kBudget      under the ledger's lock, on the run's totals after this collapse.
// A rule's state changes are proposed in its check (new face side quadwords, the budget delta)
// and written by the kernel's commit step under the same locks, or spent by the ledger.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "engine/coverage.h"
#include "engine/fan_separation.h"
#include "engine/line_coverage.h"
#include "engine/mechanics.h"
#include "engine/point_copies.h"
#include "engine/quadword.h"
#include "engine/ring.h"
#include "engine/simplify.h"
#include "engine/star.h"
#include "engine/triangle_intersection.h"
#include "engine/vec.h"

namespace femsimp {

// The fan faces of V that survive the collapse, as (V, b, c) before and (Vd, b, c) after; for a
// full-edge collapse (engine/star.h) every surviving star face, as (V or Vd, b, c) before and
// (P, b, c) after, with vd = P: the first fan_faces come from V's fan.
struct CollapseGeometry {
  int faces = 0;
  int fan_faces = 0;
  DVec3 old_normal[kMaxStar];  // unnormalised (twice the area)
  DVec3 new_normal[kMaxStar];
  DVec3 b[kMaxStar], c[kMaxStar], vd;
  // The corner that moves, before, per face (full-edge collapses only: the kernel's storage).
  const DVec3* old_apex = nullptr;

  void Build(const Ring& ring, int target_index);
  // apex: room for star.count points, which old_apex then points to.
  void Build(const EdgeStar& star, DVec3* apex);

  // Smallest cosine between old and new normals, computed once per Build: the normal rule
  // tests it and the kernel ranks directions by it (largest bends the surface least).
  double MinNormalCosine() const;

 private:
  mutable double min_normal_cosine_ = 2.0;  // 2: not computed yet
};

// The directions V may collapse along: any neighbour, only the two neighbours on the line V
// lies on (a feature line; a boundary is one), or none (V is a corner and becomes kFixed).
struct Directions {
  bool fixed = false;
  int line[2] = {-1, -1};  // fan indices of the line neighbours, when on a line
  bool on_line() const { return line[0] >= 0; }
  bool Allows(int i) const { return !on_line() || i == line[0] || i == line[1]; }
  // The line neighbour V leaves behind when it slides to line neighbour i; -1 off a line.
  int LineOther(int i) const { return !on_line() ? -1 : i == line[0] ? line[1] : line[0]; }
};

// Reads beyond the two one-rings, through the kernel's memory port. A false return means the
// view was stale (a concurrent or cached copy that no longer holds).
class NeighbourhoodReader {
 public:
  virtual ~NeighbourhoodReader() = default;
  // Faces around u, counted up to `limit`, and whether u lies on a boundary.
  virtual bool CountFan(uint32_t u, int limit, int* faces, bool* boundary) = 0;
  // The vertices joined to u, into out[0..kMaxRing]: their number, or -1 when the view was
  // stale, or kMaxRing + 2 when u has more than out holds.
  virtual int Neighbours(uint32_t u, uint32_t* out) = 0;
};

// One proposed collapse V -> Vd = fan->nbr[target]: what the rules judge, and what the
// fidelity rules propose for the commit.
struct CollapseProposal {
  const Ring* fan = nullptr;  // V's one-ring
  // Changes whenever the kernel reads `fan` again, and differs between kernels: a rule may keep
  // work on the fan alone (the same for every direction of a candidate) keyed by it. 0: unknown
  // (nothing may be kept).
  uint64_t fan_serial = 0;
  // cos^2 of the smallest angle of V's fan faces, for the relaxed minimum-angle rule: the same
  // for every direction of a candidate, so computed once (negative: not yet).
  double fan_smallest_angle_cos2 = -1.0;
  int target = -1;
  int line_other = -1;  // Directions::LineOther(target)
  CollapseGeometry geometry;

  // kTopology: Vd's one-ring, and the vertices opposite V - Vd in the faces it deletes.
  const Ring* target_fan = nullptr;
  int deleted = 0;
  uint32_t opposite[2] = {kNone, kNone};
  NeighbourhoodReader* reader = nullptr;

  // kFidelity: the fan faces' side quadwords as read, and as they will be written.
  const FaceAttrQ* fan_attr = nullptr;
  FaceAttrQ new_attr[kMaxRing];
  CollapseDelta delta;
  bool mass_measured = false;
  uint32_t cycles = 0;  // modeled SPU cycles of the fidelity work (cell back end)

  // Cells of the face index (engine/face_grid.h) this candidate holds, from the first check
  // that needs them until the candidate is done.
  std::vector<uint32_t> held_cells;
  bool cells_acquired = false;
  bool cells_for_star = false;  // held over the box of the star onto cells_vd
  uint32_t cells_vd = kNone;
  // The faces in those cells but outside V's fan that some new triangle of any direction could
  // meet (by their boxes), as they are while the cells are held, and their ids; read by the
  // first direction that needs them (nearby_read).
  bool nearby_read = false;
  std::vector<uint32_t> nearby_faces;
  std::vector<PreparedTriangle> nearby;
  // When V's ring winds once around it seen along its fan's normal and the first direction's
  // new triangles turn its way (engine/fan_separation.h), the faces shown beside it are left out
  // of `nearby`; a later direction the certificate does not cover reads them again
  // (nearby_separated false). Kept on the heap: the kernel's stack is the SPE's.
  std::unique_ptr<FanSeparation> separation;
  bool nearby_separated = false;
  // Compound collapses (engine/seam_collapse.h): faces the compound's other collapses rewrite;
  // the compound tests its new triangles against each other itself.
  std::span<const uint32_t> also_replaced;

  // A full-edge collapse (option placement = optimal): V and Vd merge at star->p; the rules
  // judge the star. Null for the paper's half-edge collapse.
  const EdgeStar* star = nullptr;
  // kFidelity, full-edge collapses: the side quadwords of Vd's other faces (star face
  // fan_faces + k), as read and as they will be written.
  const FaceAttrQ* extra_attr = nullptr;
  FaceAttrQ* new_extra_attr = nullptr;

  // The measured deviation check (engine/coverage.h): which new face takes which piece. On the
  // heap, made by that rule's first check: the kernel's state on the cell back end lives in an
  // SPE software thread's small stack, and that back end never runs the check.
  std::unique_ptr<CoveragePlan> coverage;
  // Its hold on feature lines (engine/line_coverage.h), for a collapse along a line.
  std::unique_ptr<LinePlan> line_plan;

  uint32_t vd() const { return fan->nbr[target]; }
  // Fan face f is one of the two that contain V - Vd (and disappear).
  bool IsDeleted(int f) const {
    const int n = fan->neighbours();
    return f == target || (f + 1) % n == target;
  }
};

enum class RuleStage : uint32_t {
  kDirections = 1,
  kShape = 2,
  kTopology = 4,
  kFidelity = 8,
  kBudget = 16,
  kScreen = 32,  // runs between kShape and kTopology (the list above)
};

// The stage bits of a rule that takes part in the given stages.
template <class... S>
constexpr uint32_t Stages(S... stages) {
  return (static_cast<uint32_t>(stages) | ...);
}

// kConflict: another context holds what the check needs (a lock conflict: try again later).
enum class Verdict { kPass, kReject, kStale, kConflict };

// What the rules of a run may need to know about the mesh and the run (set up once).
struct RuleSetup {
  double cos_feature = 0.0;  // a feature line turning more than this at a vertex is a corner
  float tolerance = 0.0f;    // > 0: track the deviation bound and keep it below this
  int fields = 0;            // face fields carried (their values travel in FaceAttrQ)
  bool closed = false;       // mass properties of the solid rather than of the surface
  // The parts of an assembly (Mesh::sides(), MeasurePartVolumes of the input); empty without.
  const std::vector<FaceSides>* sides = nullptr;
  const std::vector<double>* part_volumes = nullptr;
  double diagonal = 1.0;               // of the input's bounding box
  const GroupIndex* groups = nullptr;  // dense group slots, when fields are carried
  // The input's measures the budget rules' ledger starts from; its second moment is about
  // mass_origin (the input's centroid).
  const MassProperties* mass = nullptr;
  DVec3 mass_origin{0, 0, 0};
  const FieldResultants* resultants = nullptr;
  // The face index of the self-intersection rule, when it is on.
  class FaceGrid* face_grid = nullptr;
  // Every face carries its own tolerance (FaceAttrQ::limit): the wall rule's set-up ran.
  bool wall_limits = false;
  // The input's pieces (engine/coverage.h), when the tolerance is measured.
  Coverage* coverage = nullptr;
  // The input's feature lines' pieces (engine/line_coverage.h), with the coverage.
  LineCoverage* lines = nullptr;
  // An assembly cut into sheets (engine/seams.h): its seam points' copies, and its seam
  // vertices (Mesh::locked_flags; nullptr without seams).
  const PointCopies* point_copies = nullptr;
  const uint8_t* seam_vertices = nullptr;
};

class CollapseRule {
 public:
  virtual ~CollapseRule() = default;
  virtual Reject reason() const = 0;    // its name in the statistics
  virtual uint32_t stages() const = 0;  // RuleStage bits

  // kDirections: narrows the directions V may take.
  virtual void Restrict(const Ring& /*fan*/, Directions* /*directions*/) const {}
  // kShape, kTopology, kFidelity: judges the proposal (and may fill what it proposes).
  virtual Verdict Check(RuleStage /*stage*/, CollapseProposal& /*p*/) const {
    return Verdict::kPass;
  }
  // kBudget: whether the run's totals after this collapse stay within the rule's budget.
  virtual bool WithinBudget(const LedgerView& /*totals*/, const CollapseDelta& /*delta*/) const {
    return true;
  }
  // After the kernel applied the collapse, still under the locks: the rule's own state.
  virtual void Commit(CollapseProposal& /*p*/) const {}
  // The candidate is done, whatever the outcome: what the rule's checks took is given back.
  virtual void Release(CollapseProposal& /*p*/) const {}
  // Whether Commit or Release do anything (the kernel calls only those that do).
  virtual bool keeps_state() const { return false; }
  // Modeled SPU cycles per new triangle of a kShape check (the cell back end's cycle model).
  virtual uint32_t cycles_per_face() const { return 0; }
  // The side quadwords the rule's kFidelity check needs read (deviation bounds, fields).
  virtual bool reads_face_attrs() const { return false; }
  // Whether the rule spends from the mass (volume, centroid) totals of the ledger.
  virtual bool tracks_mass() const { return false; }
  // Whether the rule judges full-edge collapses (CollapseProposal::star); a run with a rule
  // that does not collapses half-edges only.
  virtual bool judges_placement() const { return true; }
  // Whether a full-edge collapse may pass where this rule (of the fidelity stage) refused the
  // half-edge one, so that the kernel tries placement after its refusal too (a budget refusal
  // always gets that try). A bound that adds up along the run does not: off the input surface
  // a vertex spends bound that later collapses no longer have (docs/FIDELITY.md § 11).
  virtual bool placement_may_pass() const { return false; }
  // Whether the rule holds a feature line that a full-edge collapse moves (V and Vd on one line,
  // merged at a point off it) within the tolerance: the kernel places vertices on lines only
  // when some rule does and every rule judges placement. The mapped bound lays the old line
  // onto the new one (BoundStarDeviation); the measured check holds the input's line pieces
  // themselves (engine/line_coverage.h).
  virtual bool holds_placed_lines() const { return false; }
  // Whether a half-edge collapse's verdict depends on V's fan alone (its one-ring's positions,
  // topology and face data): a vertex it refused is refused again until a collapse changes
  // that fan, which locks V and makes it a candidate again (RemovalKernel::Commit), so
  // reconsideration need not retry it. Rules that read further (Vd's ring, the ledger, the
  // face index) are not.
  virtual bool fan_local() const { return false; }

  bool in(RuleStage s) const { return (stages() & static_cast<uint32_t>(s)) != 0; }
};

// The rules of one run, by stage, in the order of rule_list.inc; and the ledger the budget rules
// spend from, when one is on.
class RuleSet {
 public:
  static RuleSet Build(const SimplifyOptions& options, const RuleSetup& setup);

  const std::vector<const CollapseRule*>& stage(RuleStage s) const {
    return by_stage_[StageIndex(s)];
  }
  bool reads_face_attrs() const { return reads_face_attrs_; }
  bool tracks_mass() const { return tracks_mass_; }
  bool judges_placement() const { return judges_placement_; }
  bool places_on_lines() const { return judges_placement_ && holds_placed_lines_; }
  bool placement_may_pass(Reject reason) const {
    return (placement_may_pass_ >> static_cast<int>(reason)) & 1;
  }
  // Whether the rule refusing with `reason` is fan-local (CollapseRule::fan_local).
  bool fan_local(Reject reason) const { return (fan_local_ >> static_cast<int>(reason)) & 1; }
  uint32_t shape_cycles_per_face() const { return shape_cycles_; }

  // Runs the stage's checks in order; on a refusal sets *refused to the rule's reason.
  Verdict Check(RuleStage s, CollapseProposal& p, Reject* refused) const;
  // The rules' Commit and Release hooks (engine/rule.h).
  void Commit(CollapseProposal& p) const {
    for (const CollapseRule* r : stateful_) r->Commit(p);
  }
  void Release(CollapseProposal& p) const {
    for (const CollapseRule* r : stateful_) r->Release(p);
  }
  // Spends the delta of V's collapse from the ledger if every budget rule accepts; otherwise
  // sets *refused to the first that does not and spends nothing.
  bool SpendBudgets(uint32_t v, const CollapseDelta& delta, Reject* refused) const;
  // The same for the collapses of a compound (engine/seam_collapse.h), outside rounds: all
  // are spent or none (MechanicsLedger::TryCommitTogether).
  bool SpendBudgetsTogether(std::span<const CollapseDelta> deltas, Reject* refused) const;
  // Deterministic rounds (engine/rounds.h): the ledger judges the round's collapses by their
  // share of it (MechanicsLedger::BeginRound). No-ops without budget rules.
  void BeginRound(size_t winners) const {
    if (ledger_) ledger_->BeginRound(winners);
  }
  void EndRound() const {
    if (ledger_) ledger_->EndRound();
  }

 private:
  static int StageIndex(RuleStage s);
  // Every budget rule accepts the totals with `judged`; else *refused names the first that does
  // not.
  bool WithinBudgets(const LedgerView& totals, const CollapseDelta& judged, Reject* refused) const;

  std::vector<std::unique_ptr<CollapseRule>> rules_;
  std::vector<const CollapseRule*> by_stage_[6];
  std::vector<const CollapseRule*> stateful_;
  bool reads_face_attrs_ = false;
  bool tracks_mass_ = false;
  bool judges_placement_ = true;
  bool holds_placed_lines_ = false;
  uint32_t placement_may_pass_ = 0;  // a bit per Reject reason
  uint32_t fan_local_ = 0;           // bit per Reject
  uint32_t shape_cycles_ = 0;
  std::unique_ptr<MechanicsLedger> ledger_;
};

}  // namespace femsimp
