#include "engine/features.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>

#include "engine/port.h"
#include "engine/vec.h"

namespace femsimp {
namespace {

DVec3 FaceNormal(const Mesh& mesh, uint32_t f) {
  const VertexQ* v = mesh.vertices();
  const HalfEdgeQ* h = mesh.halfedges();
  const VertexQ& a = v[h[3 * f].target];
  const VertexQ& b = v[h[3 * f + 1].target];
  const VertexQ& c = v[h[3 * f + 2].target];
  const DVec3 pa{a.x, a.y, a.z}, pb{b.x, b.y, b.z}, pc{c.x, c.y, c.z};
  return Cross(pb - pa, pc - pa);
}

}  // namespace

bool TurnsSharply(const Vec3& a, const Vec3& v, const Vec3& b, double cos_limit) {
  const DVec3 in = ToD(v) - ToD(a), out = ToD(b) - ToD(v);
  const double len = Norm(in) * Norm(out);
  return !(len > 0.0) || Dot(in, out) < cos_limit * len;
}

FeatureSummary MarkFeatures(Mesh& mesh, double feature_angle_deg,
                            const std::function<bool()>& cancelled, WorkerPool* pool) {
  const double cos_limit = std::cos(feature_angle_deg * std::numbers::pi / 180.0);
  HalfEdgeQ* h = mesh.halfedges();
  std::atomic<uint32_t>* status = mesh.status();
  std::atomic<uint64_t> feature_edges{0}, boundary_edges{0}, corner_vertices{0};
  // Chunks of kChunk items taken in turn by the pool's contexts; each polls `cancelled` first.
  constexpr uint32_t kChunk = 1u << 16;
  const auto run = [&](uint32_t count, const auto& body) {
    return RunChunked(pool, count, kChunk, cancelled, body);
  };
  // The lower half-edge of an edge decides for both halves and marks both: every flag has one
  // writer whatever the contexts, and each edge's two normals are computed once.
  const bool edges_done = run(mesh.halfedge_capacity(), [&](uint32_t begin, uint32_t end) {
    uint64_t features = 0, boundaries = 0;
    const auto mark = [&](uint32_t e, bool feature) {
      h[e].flags = (h[e].flags & ~kFeatureEdge) | (feature ? kFeatureEdge : 0u);
    };
    for (uint32_t e = begin; e < end; ++e) {
      const uint32_t t = h[e].twin;
      // The upper half's flags may be being written by its lower half's context: not read.
      if ((t != kNone && t < e) || (h[e].flags & kFaceRemoved)) continue;
      if (t == kNone) {
        mark(e, true);
        ++boundaries;
        ++features;
        continue;
      }
      bool feature = h[e].group != h[t].group;
      if (!feature) {
        const DVec3 n1 = FaceNormal(mesh, FaceOf(e));
        const DVec3 n2 = FaceNormal(mesh, FaceOf(t));
        feature = Dot(n1, n2) < cos_limit * Norm(n1) * Norm(n2);
      }
      mark(e, feature);
      if (!(h[t].flags & kFaceRemoved)) mark(t, feature);
      features += feature;
    }
    feature_edges.fetch_add(features, std::memory_order_relaxed);
    boundary_edges.fetch_add(boundaries, std::memory_order_relaxed);
  });
  FeatureSummary summary;
  summary.feature_edges = feature_edges.load();
  summary.boundary_edges = boundary_edges.load();
  if (!edges_done) return summary;
  run(mesh.vertex_capacity(), [&](uint32_t begin, uint32_t end) {
    NativePort port(mesh);
    Ring ring;
    uint64_t corners = 0;
    for (uint32_t v = begin; v < end; ++v) {
      const uint32_t s = status[v].load(std::memory_order_relaxed);
      if (s == kRemoved || mesh.IsLocked(v)) continue;  // locked: kFixed since Build, not a corner
      bool corner = GatherRing(port, v, ring) != RingResult::kOk;  // too wide: leave it alone
      if (!corner) {
        int count = 0, ends[2] = {0, 0};
        for (int i = 0; i < ring.neighbours(); ++i)
          if (ring.feature[i]) {
            if (count < 2) ends[count] = i;
            ++count;
          }
        corner = (count != 0 && count != 2) ||
                 (count == 2 &&
                  TurnsSharply(ring.pos[ends[0]], ring.center_pos, ring.pos[ends[1]], cos_limit));
      }
      if (corner)
        status[v].store(kFixed, std::memory_order_relaxed);
      else if (s == kFixed)
        status[v].store(kRemovable, std::memory_order_relaxed);  // marked before as a corner
      corners += corner;
    }
    corner_vertices.fetch_add(corners, std::memory_order_relaxed);
  });
  summary.corner_vertices = corner_vertices.load();
  return summary;
}

}  // namespace femsimp
