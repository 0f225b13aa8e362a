// Self-intersections of a triangle soup as it is: faces name their corners by index, so faces of
// an assembly's parts that meet at a seam share its vertices and are judged as touching there,
// not as crossing (CGAL's mesh test needs a manifold mesh, which a seam splits into copies).
// CGAL's exact predicates and its box intersection decide; the rules for faces sharing corners
// are those of CGAL's own self_intersections.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <CGAL/Cartesian_converter.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include "tests/judge/judge.h"

namespace femsimp::judge {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
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

  // Faces with no corner in common, in one plane (exactly), whose common part (constructed
  // exactly: a triangle or a polygon, not a point or a segment) has an area above a millionth
  // of the smaller face's, the rule femsimp reports by (engine/planar_overlap.h).
  bool OverlapInPlane(uint32_t a, uint32_t b) const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (Index(a, i) == Index(b, j)) return false;
    for (int j = 0; j < 3; ++j)
      if (!CGAL::coplanar(Corner(a, 0), Corner(a, 1), Corner(a, 2), Corner(b, j))) return false;
    const CGAL::Cartesian_converter<K, Exact> to_exact;
    const Exact::Triangle_3 exact_a = to_exact(Triangle(a)), exact_b = to_exact(Triangle(b));
    const auto common = CGAL::intersection(exact_a, exact_b);
    if (!common) return false;
    // CGAL 5's result is a boost::variant (a std::variant from CGAL 6 on).
    Exact::FT squared_area = 0;
    if (const auto* t = boost::get<Exact::Triangle_3>(&*common)) {
      squared_area = CGAL::squared_area((*t)[0], (*t)[1], (*t)[2]);
    } else if (const auto* polygon = boost::get<std::vector<Exact::Point_3>>(&*common)) {
      const std::vector<Exact::Point_3>& p = *polygon;  // convex, its corners in order
      Exact::Vector_3 twice(0, 0, 0);
      for (size_t i = 1; i + 1 < p.size(); ++i)
        twice = twice + CGAL::cross_product(p[i] - p[0], p[i + 1] - p[0]);
      squared_area = twice.squared_length() / 4;
    }
    const Exact::FT smaller = std::min(CGAL::squared_area(exact_a[0], exact_a[1], exact_a[2]),
                                       CGAL::squared_area(exact_b[0], exact_b[1], exact_b[2]));
    return squared_area > Exact::FT(1e-12) * smaller;
  }

 private:
  const RawMesh& m_;
  std::vector<K::Point_3> points_;
};

// The pairs of faces with a plane (degenerate ones have none to cross or share; the topology
// checks count them) whose boxes meet, for which `test(soup, a, b)` holds.
template <class Test>
size_t CountPairs(const RawMesh& mesh, Test test) {
  const Soup soup(mesh);
  std::vector<Box> boxes;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (soup.Degenerate(f)) continue;
    const CGAL::Bbox_3 b =
        soup.Corner(f, 0).bbox() + soup.Corner(f, 1).bbox() + soup.Corner(f, 2).bbox();
    boxes.emplace_back(b, f);
  }
  size_t pairs = 0;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    pairs += test(soup, a.info(), b.info());
  });
  return pairs;
}

}  // namespace

size_t SoupSelfIntersectingPairs(const RawMesh& mesh) {
  return CountPairs(mesh, [](const Soup& s, uint32_t a, uint32_t b) { return s.Intersect(a, b); });
}

size_t SoupOverlappingPairs(const RawMesh& mesh) {
  return CountPairs(mesh,
                    [](const Soup& s, uint32_t a, uint32_t b) { return s.OverlapInPlane(a, b); });
}

}  // namespace femsimp::judge
