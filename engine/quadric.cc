#include "engine/quadric.h"

#include <algorithm>
#include <limits>

namespace femsimp {

void InitQuadrics(Mesh& mesh) {
  mesh.EnsureQuadrics();
  QuadricQ* quadric = mesh.quadrics();
  std::fill(quadric, quadric + mesh.vertex_capacity(), QuadricQ{});
  const VertexQ* v = mesh.vertices();
  const HalfEdgeQ* h = mesh.halfedges();
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (h[3 * f].flags & kFaceRemoved) continue;
    const uint32_t ids[3] = {h[3 * f].target, h[3 * f + 1].target, h[3 * f + 2].target};
    const DVec3 a{v[ids[0]].x, v[ids[0]].y, v[ids[0]].z}, b{v[ids[1]].x, v[ids[1]].y, v[ids[1]].z},
        c{v[ids[2]].x, v[ids[2]].y, v[ids[2]].z};
    const DVec3 cross = Cross(b - a, c - a);
    const double len = Norm(cross);
    if (!(len > 0.0)) continue;
    const DVec3 n = (1.0 / len) * cross;
    const double area = 0.5 * len, d = -Dot(n, a);
    const double k[10] = {n.x * n.x, n.x * n.y, n.x * n.z, n.y * n.y, n.y * n.z,
                          n.z * n.z, n.x * d,   n.y * d,   n.z * d,   d * d};
    for (uint32_t id : ids)
      for (int i = 0; i < 10; ++i) quadric[id].q[i] += static_cast<float>(area * k[i]);
  }
}

double QuadricError(const QuadricQ& q, const DVec3& x) {
  const float* m = q.q;
  const double e = m[0] * x.x * x.x + 2 * m[1] * x.x * x.y + 2 * m[2] * x.x * x.z +
                   m[3] * x.y * x.y + 2 * m[4] * x.y * x.z + m[5] * x.z * x.z +
                   2 * (m[6] * x.x + m[7] * x.y + m[8] * x.z) + m[9];
  return std::max(0.0, e);
}

void AddQuadric(QuadricQ& into, const QuadricQ& q) {
  for (int i = 0; i < 10; ++i) into.q[i] += q.q[i];
}

float QuadricCost::Cost(const Ring& ring) const {
  int features = 0;
  for (int i = 0; i < ring.neighbours(); ++i) features += ring.feature[i];
  const QuadricQ& q = quadrics_[ring.center];
  double best = std::numeric_limits<float>::max();
  for (int i = 0; i < ring.neighbours(); ++i) {
    if (features == 2 && !ring.feature[i]) continue;
    if (features == 0 && ring.boundary && i != 0 && i != ring.neighbours() - 1) continue;
    best = std::min(best, QuadricError(q, ToD(ring.pos[i])));
  }
  return static_cast<float>(best);
}

}  // namespace femsimp
