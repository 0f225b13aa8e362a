// Decimation cost per vertex, computed between passes (the mesh is not being written then).
#pragma once

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

}  // namespace femsimp
