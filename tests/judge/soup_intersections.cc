// Self-intersections of a triangle soup as it is: faces name their corners by index, so faces of
// an assembly's parts that meet at a seam share its vertices and are judged as touching there,
// not as crossing (CGAL's mesh test needs a manifold mesh, which a seam splits into copies).
// CGAL's exact predicates and its box intersection decide; the rules for faces sharing corners
// are those of CGAL's own self_intersections.
#include <cstdint>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include "tests/judge/judge.h"

namespace femsimp::judge {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t>;

class Soup {
 public:
  explicit Soup(const RawMesh& m) : m_(m) {
    points_.reserve(m.num_vertices());
    for (size_t v = 0; v < m.num_vertices(); ++v)
      points_.emplace_back(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
  }
  const K::Point_3& Corner(uint32_t f, int i) const { return points_[m_.triangles[3 * f + i]]; }
  uint32_t Index(uint32_t f, int i) const { return m_.triangles[3 * f + i]; }
  bool Degenerate(uint32_t f) const {
    return CGAL::collinear(Corner(f, 0), Corner(f, 1), Corner(f, 2));
  }
  K::Triangle_3 Triangle(uint32_t f) const { return {Corner(f, 0), Corner(f, 1), Corner(f, 2)}; }

  bool Intersect(uint32_t a, uint32_t b) const {
    int shared = 0, ia[3], ib[3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (Index(a, i) == Index(b, j)) {
          ia[shared] = i;
          ib[shared++] = j;
        }
    if (shared == 3) return true;  // the same face twice
    if (shared == 2) {
      // Along the shared edge only, unless they fold onto each other.
      const K::Point_3 &p = Corner(a, ia[0]), &q = Corner(a, ia[1]);
      const K::Point_3& r = Corner(a, 3 - ia[0] - ia[1]);
      const K::Point_3& s = Corner(b, 3 - ib[0] - ib[1]);
      return CGAL::coplanar(p, q, r, s) && CGAL::coplanar_orientation(p, q, r, s) == CGAL::POSITIVE;
    }
    if (shared == 1) {
      // Beyond the shared corner iff the edge opposite it in one meets the other.
      const int i = ia[0], j = ib[0];
      return CGAL::do_intersect(K::Segment_3(Corner(a, (i + 1) % 3), Corner(a, (i + 2) % 3)),
                                Triangle(b)) ||
             CGAL::do_intersect(K::Segment_3(Corner(b, (j + 1) % 3), Corner(b, (j + 2) % 3)),
                                Triangle(a));
    }
    return CGAL::do_intersect(Triangle(a), Triangle(b));
  }

 private:
  const RawMesh& m_;
  std::vector<K::Point_3> points_;
};

}  // namespace

size_t SoupSelfIntersectingPairs(const RawMesh& mesh) {
  const Soup soup(mesh);
  std::vector<Box> boxes;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (soup.Degenerate(f)) continue;  // no plane to cross; the topology checks count them
    const CGAL::Bbox_3 b =
        soup.Corner(f, 0).bbox() + soup.Corner(f, 1).bbox() + soup.Corner(f, 2).bbox();
    boxes.emplace_back(b, f);
  }
  size_t pairs = 0;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    pairs += soup.Intersect(a.info(), b.info());
  });
  return pairs;
}

}  // namespace femsimp::judge
