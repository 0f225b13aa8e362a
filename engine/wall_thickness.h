// The local wall thickness of a closed part (docs/FIDELITY.md § 5, the wall rule): for each face,
// how far the solid reaches straight in under it, measured by rays from a few points of the face
// along its inward normal to the nearest other face they meet.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "engine/mesh.h"
#include "engine/worker_pool.h"

namespace femsimp {

inline constexpr float kNoWall = std::numeric_limits<float>::infinity();

// Per face (indexed by face id; removed faces get kNoWall), the smallest distance from its
// centroid and the midpoints between the centroid and its corners, along the normal pointing
// into the solid (`outward`: the faces' normals point out of it, the mesh encloses a positive
// volume), to the nearest other face; kNoWall where no ray meets one (a ray leaving through a
// crack of the surface) or no farther than `reach`. Runs on the pool's contexts; polls
// `cancelled` (may be empty) and returns an empty vector once it says true.
std::vector<float> WallThickness(const Mesh& mesh, bool outward, WorkerPool* pool,
                                 const std::function<bool()>& cancelled = {},
                                 double reach = std::numeric_limits<double>::infinity());

// What the wall rule's set-up found: the share of the surface's area whose tolerance the walls
// lowered, and the thinnest wall measured (kNoWall: none met).
struct WallLimits {
  double limited_area_share = 0.0;
  double thinnest = kNoWall;
};

// Gives every live face its own tolerance, FaceAttrQ::limit = min(tolerance, share x its wall
// thickness) (the face attributes must be allocated). Empty when `cancelled` said true.
std::optional<WallLimits> SetWallLimits(Mesh& mesh, double share, float tolerance, bool outward,
                                        WorkerPool* pool,
                                        const std::function<bool()>& cancelled = {});

}  // namespace femsimp
