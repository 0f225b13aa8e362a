// Garland-Heckbert quadric error: the summed squared distance to the planes of the faces a
// vertex has absorbed, area-weighted. The quadric cost orders candidates by it and the kernel
// then tries the collapse direction with the smallest error first.
#pragma once

#include "engine/cost.h"
#include "engine/mesh.h"
#include "engine/vec.h"

namespace femsimp {

// Sets every live vertex's quadric to the sum of its faces' plane quadrics.
void InitQuadrics(Mesh& mesh);
double QuadricError(const QuadricQ& q, const DVec3& x);  // >= 0
void AddQuadric(QuadricQ& into, const QuadricQ& q);

// Cheapest allowed collapse of the vertex under its own quadric (a vertex on a feature line
// only along the line).
class QuadricCost final : public VertexCost {
 public:
  explicit QuadricCost(const QuadricQ* quadrics) : quadrics_(quadrics) {}
  float Cost(const Ring& ring) const override;

 private:
  const QuadricQ* quadrics_;
};

}  // namespace femsimp
