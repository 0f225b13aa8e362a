#include "engine/io/polygons.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "engine/plane_fill.h"
#include "engine/vec.h"

namespace femsimp {
namespace {

struct Point2 {
  double u, v;
};

double Cross2(const Point2& a, const Point2& b, const Point2& c) {
  return (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
}

// The smallest angle of the triangle abc (radians; 0 when degenerate).
double SmallestAngle(const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3 p[3] = {a, b, c};
  double smallest = M_PI;
  for (int i = 0; i < 3; ++i) {
    const DVec3 e1 = p[(i + 1) % 3] - p[i], e2 = p[(i + 2) % 3] - p[i];
    const double l = Norm(e1) * Norm(e2);
    if (!(l > 0)) return 0;
    smallest = std::min(smallest, std::acos(std::clamp(Dot(e1, e2) / l, -1.0, 1.0)));
  }
  return smallest;
}

// Cuts one polygon (its corners' vertex ids) into triangles appended to `out`, in its winding.
void CutPolygon(const uint32_t* ids, uint32_t n, const RawMesh& mesh, std::vector<uint32_t>* out) {
  std::array<DVec3, kMaxPolygonCorners> p;
  for (uint32_t i = 0; i < n; ++i) {
    const float* x = &mesh.positions[3 * size_t(ids[i])];
    p[i] = {x[0], x[1], x[2]};
  }
  // Newell's normal; the plane drops its largest axis, its sign keeping the winding counter-
  // clockwise in the plane.
  std::array<std::array<double, 3>, kMaxPolygonCorners> corners;
  for (uint32_t i = 0; i < n; ++i) corners[i] = {p[i].x, p[i].y, p[i].z};
  const std::array<double, 3> newell = NewellNormal(corners.data(), n);
  const DVec3 normal{newell[0], newell[1], newell[2]};
  const double ax = std::fabs(normal.x), ay = std::fabs(normal.y), az = std::fabs(normal.z);
  const int drop = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
  const double sign = (drop == 0 ? normal.x : drop == 1 ? normal.y : normal.z) < 0 ? -1.0 : 1.0;
  std::array<Point2, kMaxPolygonCorners> q;
  for (uint32_t i = 0; i < n; ++i) {
    const double c[3] = {p[i].x, p[i].y, p[i].z};
    const double u = c[(drop + 1) % 3], v = c[(drop + 2) % 3];
    q[i] = {u, sign * v};
  }
  std::array<uint32_t, kMaxPolygonCorners> left;
  uint32_t m = n;
  for (uint32_t i = 0; i < n; ++i) left[i] = i;
  while (m > 3) {
    // The ear whose triangle's smallest angle is largest: convex in the plane, and no other
    // remaining corner inside or on it.
    int best = -1;
    double best_angle = -1;
    for (uint32_t k = 0; k < m; ++k) {
      const uint32_t a = left[(k + m - 1) % m], b = left[k], c = left[(k + 1) % m];
      if (!(Cross2(q[a], q[b], q[c]) > 0)) continue;
      bool empty = true;
      for (uint32_t j = 0; j < m && empty; ++j) {
        const uint32_t d = left[j];
        if (d == a || d == b || d == c) continue;
        empty = !(Cross2(q[a], q[b], q[d]) >= 0 && Cross2(q[b], q[c], q[d]) >= 0 &&
                  Cross2(q[c], q[a], q[d]) >= 0);
      }
      if (!empty) continue;
      const double angle = SmallestAngle(p[a], p[b], p[c]);
      if (angle > best_angle) {
        best_angle = angle;
        best = int(k);
      }
    }
    if (best < 0) break;  // no ear (a polygon crossing itself, or degenerate): a fan below
    const uint32_t k = uint32_t(best);
    out->insert(out->end(), {ids[left[(k + m - 1) % m]], ids[left[k]], ids[left[(k + 1) % m]]});
    std::copy(left.begin() + k + 1, left.begin() + m, left.begin() + k);
    --m;
  }
  // What is left is a triangle, or a polygon with no ear: its fan, whose bad triangles repair
  // reports like any other degenerate or folded facet.
  for (uint32_t k = 1; k + 1 < m; ++k)
    out->insert(out->end(), {ids[left[0]], ids[left[k]], ids[left[k + 1]]});
}

}  // namespace

absl::Status TriangulatePolygons(const std::vector<PolygonFace>& polygons, RawMesh* mesh,
                                 std::vector<size_t>* face_lines, std::string* summary) {
  if (polygons.empty()) return absl::OkStatus();
  const size_t nv = mesh->num_vertices();
  const std::vector<uint32_t> corners = std::move(mesh->triangles);
  mesh->triangles.clear();
  mesh->triangles.reserve(corners.size() + 3 * polygons.size());
  size_t in_polygons = 0;
  for (const PolygonFace& polygon : polygons) in_polygons += polygon.corners;
  const size_t faces = polygons.size() + (corners.size() - in_polygons) / 3;
  // Per-face data (one per face of the file) follows its face; anything else is left alone.
  const bool lines = face_lines != nullptr && face_lines->size() == faces;
  const bool groups = mesh->face_groups.size() == faces;
  std::vector<uint32_t> new_groups;
  std::vector<std::vector<float>> new_fields(mesh->face_fields.size());
  std::vector<size_t> new_lines;
  size_t at = 0, next = 0, triangles_made = 0;
  uint32_t largest = 0;
  for (size_t face = 0; at < corners.size(); ++face) {
    const bool polygon = next < polygons.size() && polygons[next].face == face;
    const uint32_t n = polygon ? polygons[next].corners : 3;
    if (polygon) ++next;
    if (n < 3 || n > kMaxPolygonCorners || at + n > corners.size())
      return absl::InternalError(absl::StrCat("polygons: face ", face, " of ", n,
                                              " corners does not fit the corner list"));
    for (uint32_t c = 0; c < n; ++c)
      if (corners[at + c] >= nv)
        return absl::InvalidArgumentError(absl::StrCat(
            "face ", face, lines ? absl::StrCat(" (line ", (*face_lines)[face], ")") : "",
            " references vertex ", corners[at + c], " but the file has ", nv, " vertices"));
    const size_t before = mesh->triangles.size();
    if (polygon) {
      CutPolygon(&corners[at], n, *mesh, &mesh->triangles);
      largest = std::max(largest, n);
      triangles_made += n - 2;
    } else {
      mesh->triangles.insert(mesh->triangles.end(), &corners[at], &corners[at] + 3);
    }
    for (size_t t = before; t < mesh->triangles.size(); t += 3) {
      if (groups) new_groups.push_back(mesh->face_groups[face]);
      for (size_t k = 0; k < new_fields.size(); ++k)
        if (mesh->face_fields[k].values.size() == faces)
          new_fields[k].push_back(mesh->face_fields[k].values[face]);
      if (lines) new_lines.push_back((*face_lines)[face]);
    }
    at += n;
  }
  if (groups) mesh->face_groups = std::move(new_groups);
  for (size_t k = 0; k < new_fields.size(); ++k)
    if (mesh->face_fields[k].values.size() == faces)
      mesh->face_fields[k].values = std::move(new_fields[k]);
  if (lines) *face_lines = std::move(new_lines);
  *summary = absl::StrCat("polygons: cut ", polygons.size(),
                          polygons.size() == 1 ? " polygon" : " polygons", " (up to ", largest,
                          " corners) into ", triangles_made,
                          " triangles; facet numbers from here on count these triangles");
  return absl::OkStatus();
}

}  // namespace femsimp
