// Feature edges and corners, marked once before the passes (docs/FIDELITY.md): the kernel then
// lets a vertex on a feature line slide only along that line, and never removes a corner.
#pragma once

#include <cstdint>
#include <functional>

#include "engine/mesh.h"
#include "engine/ring.h"
#include "engine/worker_pool.h"

namespace femsimp {

struct FeatureSummary {
  uint64_t feature_edges = 0;    // undirected
  uint64_t boundary_edges = 0;   // a subset of the feature edges
  uint64_t corner_vertices = 0;  // set to kFixed
};

// A feature edge is a boundary edge, a border between two face groups, or an edge whose faces'
// normals differ by more than feature_angle_deg. A vertex where one or three or more feature
// edges meet, or where its two feature edges turn by more than feature_angle_deg, is a corner.
// `cancelled` (may be empty) is polled every 64Ki edges and vertices; once it says true the
// marks are left half made, and the mesh must not be simplified with them. With a pool its
// contexts share the work; the marks and counts do not depend on how many there are.
FeatureSummary MarkFeatures(Mesh& mesh, double feature_angle_deg,
                            const std::function<bool()>& cancelled = {},
                            WorkerPool* pool = nullptr);

// True when the line a -> v -> b turns by more than the angle whose cosine is cos_limit.
bool TurnsSharply(const Vec3& a, const Vec3& v, const Vec3& b, double cos_limit);

}  // namespace femsimp
