// Decimation criteria: small units with one job each, judged on the geometry of one proposed
// half-edge collapse V -> Vd (the surviving fan faces of V before and after).
#pragma once

#include <memory>
#include <vector>

#include "engine/ring.h"
#include "engine/simplify.h"
#include "engine/vec.h"

namespace femsimp {

// The fan faces of V that survive the collapse, as (V, b, c) before and (Vd, b, c) after.
struct CollapseGeometry {
  int faces = 0;
  DVec3 old_normal[kMaxRing];  // unnormalised (twice the area)
  DVec3 new_normal[kMaxRing];
  DVec3 b[kMaxRing], c[kMaxRing], vd;

  void Build(const Ring& ring, int target_index);

  // Smallest cosine between old and new normals, computed once per Build: the normal
  // criterion tests it and the kernel ranks directions by it (largest bends the surface least).
  double MinNormalCosine() const;

 private:
  mutable double min_normal_cosine_ = 2.0;  // 2: not computed yet
};

class CollapseCriterion {
 public:
  virtual ~CollapseCriterion() = default;
  virtual Reject reason() const = 0;
  virtual bool Accept(const CollapseGeometry& g) const = 0;
  // Modeled SPU cycles per new triangle (the cell back end's cycle model).
  virtual uint32_t cycles_per_face() const = 0;
};

// No new triangle may be (almost) flat.
class DegenerateCriterion final : public CollapseCriterion {
 public:
  Reject reason() const override { return Reject::kDegenerate; }
  bool Accept(const CollapseGeometry& g) const override;
  uint32_t cycles_per_face() const override { return 20; }
};

// No new triangle may turn over against the one it replaces.
class FoldOverCriterion final : public CollapseCriterion {
 public:
  Reject reason() const override { return Reject::kFoldOver; }
  bool Accept(const CollapseGeometry& g) const override;
  uint32_t cycles_per_face() const override { return 8; }
};

// Every interior angle of every new triangle at least min_angle (paper: 10 degrees).
class MinAngleCriterion final : public CollapseCriterion {
 public:
  explicit MinAngleCriterion(double degrees);
  Reject reason() const override { return Reject::kMinAngle; }
  bool Accept(const CollapseGeometry& g) const override;
  uint32_t cycles_per_face() const override { return 60; }

 private:
  double cos_max_;  // cos(min_angle): an angle is too small when its cosine exceeds this
};

// Each new triangle's normal within max_deviation of the old triangle's (paper: 25 degrees).
class NormalDeviationCriterion final : public CollapseCriterion {
 public:
  explicit NormalDeviationCriterion(double degrees);
  Reject reason() const override { return Reject::kNormalDeviation; }
  bool Accept(const CollapseGeometry& g) const override;
  uint32_t cycles_per_face() const override { return 50; }

 private:
  double cos_min_;
};

// The criteria for a run, in the order they are checked (cheapest and most selective first).
class CriteriaSet {
 public:
  static CriteriaSet FromOptions(const SimplifyOptions& options);
  // Returns true or sets *failed to the first criterion that rejects.
  bool Accept(const CollapseGeometry& g, Reject* failed) const;
  // Modeled cycles per triangle when every criterion runs (the geometry itself is extra).
  uint32_t CyclesPerFace() const;

 private:
  std::vector<std::unique_ptr<CollapseCriterion>> criteria_;
};

}  // namespace femsimp
