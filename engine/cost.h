// Decimation cost per vertex, computed between passes (the mesh is not being written then).
#pragma once

#include "engine/quadword.h"
#include "engine/ring.h"

namespace femsimp {

class VertexCost {
 public:
  virtual ~VertexCost() = default;
  // Lower is removed first; must be >= 0.
  virtual float Cost(const Ring& ring) const = 0;
};

// The paper's cost: discrete Gaussian curvature as the angle deficit |2pi - sum of angles| of
// an interior vertex; on a boundary the geodesic curvature |pi - sum| (a straight boundary
// point is as cheap as a flat interior one).
class GaussianCurvatureCost final : public VertexCost {
 public:
  float Cost(const Ring& ring) const override;
};

// For runs with a tolerance: the largest deviation bound its fan's faces already carry, as a
// share of the tolerance, so that the tolerance is spent evenly over the surface rather than
// used up where the first collapses stacked; ties (every bound is 0 in the first pass) go by
// the Gaussian curvature. Keeps 0-21 % fewer vertices than the curvature alone at the same
// guarantee (docs/FIDELITY.md § 6).
class DeviationCost final : public VertexCost {
 public:
  DeviationCost(const FaceAttrQ* face_attrs, float tolerance)
      : face_attrs_(face_attrs), tolerance_(tolerance) {}
  float Cost(const Ring& ring) const override;

 private:
  const FaceAttrQ* face_attrs_;
  float tolerance_;
  GaussianCurvatureCost curvature_;
};

}  // namespace femsimp
