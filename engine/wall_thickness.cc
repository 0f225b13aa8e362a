#include "engine/wall_thickness.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "engine/vec.h"

namespace femsimp {
namespace {

void FaceCorners(const Mesh& mesh, uint32_t f, DVec3* p) {
  for (int k = 0; k < 3; ++k) {
    const VertexQ& q = mesh.vertices()[mesh.halfedges()[3 * f + k].target];
    p[k] = {q.x, q.y, q.z};
  }
}

// A bounding-volume hierarchy over the live faces, for nearest-hit ray queries. Built once, read
// by every context.
class FaceTree {
 public:
  explicit FaceTree(const Mesh& mesh) {
    for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
      if (mesh.IsFaceRemoved(f)) continue;
      Triangle t;
      t.face = f;
      FaceCorners(mesh, f, t.p);
      triangles_.push_back(t);
    }
    if (triangles_.empty()) return;
    nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
    Build(0, static_cast<uint32_t>(triangles_.size()));
  }

  // The smallest t in (0, reach) at which o + t d meets a face other than `skip`; infinity when
  // none.
  double Nearest(const DVec3& o, const DVec3& d, uint32_t skip, double reach) const {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    double best = reach;
    if (nodes_.empty()) return kNone;
    const double inv[3] = {1.0 / d.x, 1.0 / d.y, 1.0 / d.z};
    const double org[3] = {o.x, o.y, o.z};
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      // A box the ray misses enters at infinity: skipped even before any hit.
      if (!(Entry(n, org, inv) < best)) continue;
      if (n.count > 0) {
        for (uint32_t i = n.first; i < n.first + n.count; ++i)
          if (triangles_[i].face != skip) best = std::min(best, Hit(triangles_[i], o, d));
        continue;
      }
      // Children: this + 1 and n.first. The nearer one is popped first.
      const uint32_t left = static_cast<uint32_t>(&n - nodes_.data()) + 1, right = n.first;
      const double tl = Entry(nodes_[left], org, inv), tr = Entry(nodes_[right], org, inv);
      if (top + 2 > 64) continue;  // deeper than a balanced tree of 2^60 faces: never
      const uint32_t near = tl <= tr ? left : right, far = tl <= tr ? right : left;
      if (std::max(tl, tr) < best) stack[top++] = far;
      if (std::min(tl, tr) < best) stack[top++] = near;
    }
    return best < reach ? best : kNone;
  }

 private:
  static constexpr uint32_t kLeafSize = 4;

  struct Triangle {
    DVec3 p[3];
    uint32_t face;
    DVec3 centroid() const { return (1.0 / 3.0) * (p[0] + p[1] + p[2]); }
  };
  struct Node {
    double lo[3], hi[3];
    uint32_t first;  // leaf: its first triangle; inner node: its right child (left: the next)
    uint32_t count;  // triangles of a leaf; 0 for an inner node
  };

  // Nodes in depth-first order, so that a node's left child follows it.
  void Build(uint32_t begin, uint32_t end) {
    const uint32_t index = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    Node box{};
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::numeric_limits<double>::infinity();
      box.hi[a] = -box.lo[a];
    }
    for (uint32_t i = begin; i < end; ++i)
      for (const DVec3& p : triangles_[i].p) {
        const double c[3] = {p.x, p.y, p.z};
        for (int a = 0; a < 3; ++a) {
          box.lo[a] = std::min(box.lo[a], c[a]);
          box.hi[a] = std::max(box.hi[a], c[a]);
        }
      }
    if (end - begin <= kLeafSize) {
      box.first = begin;
      box.count = end - begin;
      nodes_[index] = box;
      return;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
    const uint32_t mid = begin + (end - begin) / 2;
    const auto key = [axis](const Triangle& t) {
      const DVec3 c = t.centroid();
      return axis == 0 ? c.x : axis == 1 ? c.y : c.z;
    };
    std::nth_element(triangles_.begin() + begin, triangles_.begin() + mid, triangles_.begin() + end,
                     [&](const Triangle& a, const Triangle& b) { return key(a) < key(b); });
    Build(begin, mid);
    box.first = static_cast<uint32_t>(nodes_.size());
    box.count = 0;
    Build(mid, end);
    nodes_[index] = box;
  }

  // Where the ray enters the node's box (0 when it starts inside), or infinity when it misses.
  static double Entry(const Node& n, const double* o, const double* inv) {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      double ta = (n.lo[a] - o[a]) * inv[a], tb = (n.hi[a] - o[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      // A ray parallel to the slab gives NaN when it starts on its face: keep it in.
      if (!(ta <= t0)) t0 = std::isnan(ta) ? t0 : ta;
      if (!(tb >= t1)) t1 = std::isnan(tb) ? t1 : tb;
      if (t0 > t1) return std::numeric_limits<double>::infinity();
    }
    return t0;
  }

  // Möller-Trumbore, edges included (a ray through an edge or a corner meets the surface).
  static double Hit(const Triangle& t, const DVec3& o, const DVec3& d) {
    constexpr double kEdge = 1e-9;
    const DVec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0];
    const DVec3 q = Cross(d, e2);
    const double det = Dot(e1, q);
    if (det == 0.0) return std::numeric_limits<double>::infinity();
    const double inv = 1.0 / det;
    const DVec3 s = o - t.p[0];
    const double u = Dot(s, q) * inv;
    if (u < -kEdge || u > 1.0 + kEdge) return std::numeric_limits<double>::infinity();
    const DVec3 r = Cross(s, e1);
    const double w = Dot(d, r) * inv;
    if (w < -kEdge || u + w > 1.0 + kEdge) return std::numeric_limits<double>::infinity();
    const double dist = Dot(e2, r) * inv;
    return dist > 0.0 ? dist : std::numeric_limits<double>::infinity();
  }

  std::vector<Triangle> triangles_;
  std::vector<Node> nodes_;
};

}  // namespace

std::vector<float> WallThickness(const Mesh& mesh, bool outward, WorkerPool* pool,
                                 const std::function<bool()>& cancelled, double reach) {
  const FaceTree tree(mesh);
  const uint32_t faces = mesh.face_capacity();
  std::vector<float> thickness(faces, kNoWall);
  const auto measure = [&](uint32_t f) {
    DVec3 p[3];
    FaceCorners(mesh, f, p);
    const DVec3 n = Cross(p[1] - p[0], p[2] - p[0]);
    const double length = Norm(n);
    if (!(length > 0.0)) return kNoWall;
    const DVec3 in = (outward ? -1.0 : 1.0) / length * n;
    const DVec3 c = (1.0 / 3.0) * (p[0] + p[1] + p[2]);
    double t = tree.Nearest(c, in, f, reach);
    for (const DVec3& corner : p) t = std::min(t, tree.Nearest(0.5 * (c + corner), in, f, reach));
    return std::isinf(t) ? kNoWall : static_cast<float>(t);
  };

  const bool done = RunChunked(pool, faces, 4096, cancelled, [&](uint32_t begin, uint32_t end) {
    for (uint32_t f = begin; f < end; ++f)
      if (!mesh.IsFaceRemoved(f)) thickness[f] = measure(f);
  });
  if (!done) return {};
  return thickness;
}

std::optional<WallLimits> SetWallLimits(Mesh& mesh, double share, float tolerance, bool outward,
                                        WorkerPool* pool, const std::function<bool()>& cancelled) {
  // A wall at least tolerance / share thick leaves the face the whole tolerance: rays stop there.
  const std::vector<float> thickness =
      WallThickness(mesh, outward, pool, cancelled, double(tolerance) / share);
  if (thickness.empty() && mesh.face_capacity() > 0) return std::nullopt;
  FaceAttrQ* attrs = mesh.face_attrs();
  WallLimits limits;
  double area = 0.0, limited = 0.0;
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (mesh.IsFaceRemoved(f)) continue;
    // Never 0, which FaceAttrQ::limit keeps for "none".
    const float wall =
        std::max(static_cast<float>(share * thickness[f]), std::numeric_limits<float>::min());
    attrs[f].limit = std::min(tolerance, wall);
    limits.thinnest = std::min<double>(limits.thinnest, thickness[f]);
    DVec3 p[3];
    FaceCorners(mesh, f, p);
    const double a = Norm(Cross(p[1] - p[0], p[2] - p[0]));
    area += a;
    if (wall < tolerance) limited += a;
  }
  limits.limited_area_share = area > 0.0 ? limited / area : 0.0;
  return limits;
}

}  // namespace femsimp
