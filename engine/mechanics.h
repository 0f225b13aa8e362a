// Mechanical criteria (docs/FIDELITY.md): enclosed volume, centre of mass and the resultant of
// each face field per face group, measured on a mesh and enforced as global budgets that every
// context of a run spends from under one lock.
#pragma once

#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/functional/function_ref.h"
#include "engine/inertia.h"
#include "engine/mesh.h"
#include "engine/ring.h"
#include "engine/simplify.h"
#include "engine/star.h"
#include "engine/vec.h"

namespace femsimp {

// Volume and first moment of the enclosed solid (closed meshes), or area and first moment of
// the surface (open ones): the centre of mass is moment / measure. `second` is the second moment
// about a reference point the caller chooses (the run's: the input's centroid), where it is
// measured at all.
struct MassProperties {
  double measure = 0.0;
  DVec3 moment{0, 0, 0};
  Sym3 second;
  DVec3 centroid() const { return (1.0 / measure) * moment; }
};

// Dense indices of the face group ids a mesh uses (the ledger keeps one entry per group).
class GroupIndex {
 public:
  explicit GroupIndex(const Mesh& mesh);
  int size() const { return static_cast<int>(ids_.size()); }
  int Of(uint32_t group) const { return index_.at(group); }

 private:
  absl::flat_hash_map<uint32_t, int> index_;
  std::vector<uint32_t> ids_;
};

// Sum of value * area vector, and of |value| * area (the reference for relative changes), per
// group and field: index group * kMaxFaceFields + field.
struct FieldResultants {
  std::vector<DVec3> force;
  std::vector<double> load;
};

bool IsClosed(const Mesh& mesh);
// With the second moment about `origin`. Closed: of the solid the faces bound, each face by its
// weight (Mesh::sides(): the parts of an assembly; +1 without).
MassProperties MeasureMass(const Mesh& mesh, bool closed, const DVec3& origin);
// The volume of each part of an assembly (Mesh::sides()); empty without parts. Measured from
// `origin` (near the part: no large cancelling terms).
std::vector<double> MeasurePartVolumes(const Mesh& mesh, const DVec3& origin);
// The live faces' total area.
double SurfaceArea(const Mesh& mesh);
// The same properties with the second moment about `to` instead of `from` (parallel axes).
MassProperties MovedSecondMoment(const MassProperties& m, const DVec3& from, const DVec3& to);
// Centroid and principal moments of inertia (unit density) of m, whose second moment is about
// `origin`.
MassSummary Summarize(const MassProperties& m, bool solid, const DVec3& origin);
FieldResultants MeasureFields(const Mesh& mesh, const GroupIndex& groups);
// Worst |F_after - F_before| / load_before over groups and fields (0 without fields).
double WorstFieldChange(const FieldResultants& before, const FieldResultants& after);

// What one collapse changes: the mass properties, and the resultant of the groups it touches.
struct CollapseDelta {
  MassProperties mass;  // of the solid (closed), each face by its weight; or of the surface
  // The parts of an assembly: the fan's entry in Mesh::sides(), and the volume change behind
  // its faces (the part behind gains it, the part ahead loses it).
  uint32_t sides = 0;
  double enclosed = 0.0;
  int entries = 0;
  int slot[2 * kMaxFaceFields];  // group * kMaxFaceFields + field
  DVec3 force[2 * kMaxFaceFields];
};

// The weight of a fan's faces in the solid's integrals (FaceSides::weight; 1 without parts).
inline double FanWeight(const std::vector<FaceSides>& sides, const Ring& fan) {
  return sides.empty() ? 1.0 : sides[fan.sides].weight;
}

// Mass change of collapsing V onto ring.nbr[target] (origin-independent: the two patches share
// their border, so only the enclosed difference counts), the solid's by the fan's `weight`.
void CollapseMassDelta(const Ring& ring, int target, bool closed, double weight,
                       CollapseDelta* delta);
// Adds the collapse's change of the second moment about `origin` to delta->mass.second.
void CollapseSecondMomentDelta(const Ring& ring, int target, bool closed, double weight,
                               const DVec3& origin, CollapseDelta* delta);

// The same two for a full-edge collapse (engine/star.h): the new faces at star.p replace the
// old ones; `sides` is the star's fan's.
void StarMassDelta(const EdgeStar& star, bool closed, double weight, uint32_t sides,
                   CollapseDelta* delta);
void StarSecondMomentDelta(const EdgeStar& star, bool closed, double weight, const DVec3& origin,
                           CollapseDelta* delta);

// New field values for the fan faces that survive the collapse: per group, the smallest
// area-weighted change that keeps the group's resultant over the fan; what cannot be kept
// (a group losing its last fan face, or a fan too flat to carry a sideways force) goes into
// delta->force. fan_attr / new_attr are indexed by fan face; group_slot[f] is the dense group.
void TransferFields(const Ring& ring, int target, int fields, const FaceAttrQ* fan_attr,
                    const int* group_slot, FaceAttrQ* new_attr, CollapseDelta* delta);

// A part of an assembly whose volume a collapse changes.
struct PartSpend {
  double input = 0.0;  // its volume in the input
  double spent = 0.0;  // its volume change so far, this collapse included
};

// The ledger's totals as a budget rule (engine/rule.h) sees them, under the ledger's lock.
struct LedgerView {
  const MassProperties& input;            // of the input mesh
  const MassProperties& spent;            // change so far, this collapse included
  const FieldResultants& reference;       // per group and field, of the input
  const std::vector<DVec3>& force_spent;  // resultant change so far, without this collapse
  PartSpend parts[2] = {};                // the parts behind and ahead of the collapse's faces
  int part_count = 0;
};

// The run's running totals, spent from by every context under one lock; the budget rules
// decide what may be spent.
class MechanicsLedger {
 public:
  // `sides` and `part_volumes`: the parts of an assembly (Mesh::sides(), MeasurePartVolumes),
  // empty without.
  MechanicsLedger(const MassProperties& input, const FieldResultants& fields,
                  std::vector<FaceSides> sides = {}, std::vector<double> part_volumes = {});

  // Spends the delta of V's collapse if `within` accepts the totals that `judged` would leave;
  // otherwise changes nothing and returns false. Outside rounds `judged` is the delta itself.
  bool TryCommit(uint32_t v, const CollapseDelta& delta, const CollapseDelta& judged,
                 absl::FunctionRef<bool(const LedgerView&)> within);

  // All of `deltas` or none (a compound collapse, outside rounds): each is judged by `within`
  // against the current totals with its delta scaled by their number (`judged[k]`); if all pass,
  // all are spent. The sum is then the mean of points within the budgets (convex), so within.
  bool TryCommitTogether(std::span<const CollapseDelta> deltas,
                         std::span<const CollapseDelta> judged,
                         absl::FunctionRef<bool(const LedgerView&, size_t k)> within);

  // Deterministic rounds (engine/rounds.h): until EndRound, every collapse is judged against
  // the totals at the round's start with its delta scaled by `winners` (round_scale()), and
  // the accepted deltas are added at EndRound in vertex order, so that the totals do not depend
  // on the order the collapses ran in.
  void BeginRound(size_t winners);
  void EndRound();
  double round_scale() const { return round_scale_; }

 private:
  void Add(const CollapseDelta& delta);  // under mu_
  // What the budget rules see of the totals with `judged` spent (its mass in *spent, which the
  // view refers to), under mu_.
  LedgerView ViewWith(const CollapseDelta& judged, MassProperties* spent) const;

  const MassProperties input_;
  const FieldResultants fields_;
  std::mutex mu_;
  MassProperties spent_;            // guarded by mu_
  std::vector<DVec3> force_spent_;  // guarded by mu_
  const std::vector<FaceSides> sides_;
  const std::vector<double> part_input_;
  std::vector<double> part_spent_;  // guarded by mu_
  double round_scale_ = 1.0;        // set between rounds only
  bool in_round_ = false;
  std::vector<std::pair<uint32_t, CollapseDelta>> round_deltas_;  // guarded by mu_
};

// The delta times s (the deterministic rounds judge a collapse by its share of the round).
CollapseDelta Scaled(const CollapseDelta& delta, double s);

}  // namespace femsimp
