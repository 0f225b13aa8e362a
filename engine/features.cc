#include "engine/features.h"

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
                            const std::function<bool()>& cancelled) {
  const auto poll = [&](uint32_t i) { return i % (1u << 16) == 0 && cancelled && cancelled(); };
  FeatureSummary summary;
  const double cos_limit = std::cos(feature_angle_deg * std::numbers::pi / 180.0);
  HalfEdgeQ* h = mesh.halfedges();
  for (uint32_t e = 0; e < mesh.halfedge_capacity(); ++e) {
    if (poll(e)) return summary;
    if (h[e].flags & kFaceRemoved) continue;
    const uint32_t t = h[e].twin;
    bool feature;
    if (t == kNone) {
      feature = true;
      ++summary.boundary_edges;
    } else {
      if (t < e) continue;  // each interior edge once
      if (h[e].group != h[t].group) {
        feature = true;
      } else {
        const DVec3 n1 = FaceNormal(mesh, FaceOf(e)), n2 = FaceNormal(mesh, FaceOf(t));
        feature = Dot(n1, n2) < cos_limit * Norm(n1) * Norm(n2);
      }
    }
    const uint32_t bits = feature ? kFeatureEdge : 0u;
    h[e].flags = (h[e].flags & ~kFeatureEdge) | bits;
    if (t != kNone) h[t].flags = (h[t].flags & ~kFeatureEdge) | bits;
    summary.feature_edges += feature;
  }
  NativePort port(mesh);
  Ring ring;
  std::atomic<uint32_t>* status = mesh.status();
  for (uint32_t v = 0; v < mesh.vertex_capacity(); ++v) {
    if (poll(v)) return summary;
    const uint32_t s = status[v].load(std::memory_order_relaxed);
    if (s == kRemoved || mesh.IsLocked(v)) continue;  // locked: kFixed since Build, not a corner
    if (s == kFixed) status[v].store(kRemovable, std::memory_order_relaxed);  // re-marked below
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
    if (corner) {
      status[v].store(kFixed, std::memory_order_relaxed);
      ++summary.corner_vertices;
    }
  }
  return summary;
}

}  // namespace femsimp
