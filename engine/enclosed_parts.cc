#include "engine/enclosed_parts.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <tuple>

#include "absl/container/flat_hash_map.h"
#include "engine/box_containment.h"
#include "engine/edge_groups.h"
#include "engine/point_in_shell.h"
#include "engine/union_find.h"
#include "engine/vec.h"

namespace femsimp {
namespace {

constexpr int64_t kNoComponent = -1;

DVec3 Point(const RawMesh& mesh, uint32_t v) {
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

struct Component {
  std::vector<uint32_t> faces;
  bool closed = true;
  double six_volume = 0;  // signed, about the mesh's centre
  DVec3 lo{}, hi{};
  int64_t parent = kNoComponent;  // the smallest closed component around it
  std::vector<uint32_t> children;
};

// The edge-connected components of a soup without seams, and which closed one lies directly
// inside which: the outer one's winding number about the centroids of a few facets of the
// inner, spread over it, is not 0 at any of them.
class Nesting {
 public:
  explicit Nesting(const RawMesh& mesh) : mesh_(mesh) {
    const std::vector<uint32_t>& tri = mesh.triangles;
    const uint32_t nf = static_cast<uint32_t>(mesh.num_faces());
    const EdgeGroups edges(tri);
    UnionFind pieces(nf);
    std::vector<uint8_t> open(nf, 0);
    for (size_t g = 0; g < edges.size(); ++g) {
      const uint32_t f0 = edges.half[edges.begin[g]] / 3;
      if (edges.count(g) == 1) open[f0] = 1;
      if (edges.count(g) > 2) seams_ = true;
      for (uint32_t i = edges.begin[g] + 1; i < edges.begin[g + 1]; ++i)
        pieces.Union(f0, edges.half[i] / 3);
    }
    if (seams_) return;
    const DVec3 centre = SoupCentre(mesh);
    absl::flat_hash_map<uint32_t, uint32_t> index;  // piece root -> component
    component_of_face_.resize(nf);
    for (uint32_t f = 0; f < nf; ++f) {
      const auto [it, fresh] =
          index.try_emplace(pieces.Find(f), static_cast<uint32_t>(components_.size()));
      if (fresh) {
        components_.emplace_back();
        components_.back().lo = components_.back().hi = Point(mesh, tri[3 * f]);
      }
      Component& c = components_[it->second];
      component_of_face_[f] = it->second;
      c.faces.push_back(f);
      c.closed &= !open[f];
      DVec3 p[3];
      for (int i = 0; i < 3; ++i) {
        p[i] = Point(mesh, tri[3 * f + i]);
        c.lo = {std::min(c.lo.x, p[i].x), std::min(c.lo.y, p[i].y), std::min(c.lo.z, p[i].z)};
        c.hi = {std::max(c.hi.x, p[i].x), std::max(c.hi.y, p[i].y), std::max(c.hi.z, p[i].z)};
      }
      c.six_volume += Dot(p[0] - centre, Cross(p[1] - centre, p[2] - centre));
    }
    FindParents();
  }

  bool seams() const { return seams_; }
  const std::vector<Component>& components() const { return components_; }
  uint32_t ComponentOf(uint32_t face) const { return component_of_face_[face]; }

 private:
  bool Inside(uint32_t outer, uint32_t inner) {
    const Component& o = components_[outer];
    const Component& in = components_[inner];
    std::unique_ptr<PointInShell>& test = tests_[outer];
    if (!test) {
      std::vector<uint32_t> corners;
      corners.reserve(3 * o.faces.size());
      for (const uint32_t f : o.faces)
        corners.insert(corners.end(), &mesh_.triangles[3 * f], &mesh_.triangles[3 * f + 3]);
      test = std::make_unique<PointInShell>(mesh_.positions.data(), std::move(corners));
    }
    constexpr size_t kSamples = 8;
    const size_t n = in.faces.size(), samples = std::min(n, kSamples);
    for (size_t s = 0; s < samples; ++s) {
      const uint32_t f = in.faces[s * n / samples];
      const DVec3 at = (1.0 / 3) * (Point(mesh_, mesh_.triangles[3 * f]) +
                                    Point(mesh_, mesh_.triangles[3 * f + 1]) +
                                    Point(mesh_, mesh_.triangles[3 * f + 2]));
      if (test->Winding(at) == 0) return false;
    }
    return true;
  }

  // Each closed component's parent: of those around it, the one of the smallest volume.
  void FindParents() {
    std::vector<uint32_t> closed;
    std::vector<AxisBox> boxes;
    for (uint32_t c = 0; c < components_.size(); ++c)
      if (components_[c].closed) {
        closed.push_back(c);
        const Component& k = components_[c];
        boxes.push_back({{k.lo.x, k.lo.y, k.lo.z}, {k.hi.x, k.hi.y, k.hi.z}});
      }
    tests_.resize(components_.size());
    const std::vector<std::vector<uint32_t>> candidates = ContainingBoxes(boxes);
    for (size_t i = 0; i < closed.size(); ++i) {
      Component& c = components_[closed[i]];
      for (const uint32_t o : candidates[i]) {
        const uint32_t outer = closed[o];
        if (c.parent != kNoComponent &&
            std::fabs(components_[outer].six_volume) >= std::fabs(components_[c.parent].six_volume))
          continue;
        if (Inside(outer, closed[i])) c.parent = outer;
      }
      if (c.parent != kNoComponent) components_[c.parent].children.push_back(closed[i]);
    }
  }

  const RawMesh& mesh_;
  bool seams_ = false;
  std::vector<Component> components_;
  std::vector<uint32_t> component_of_face_;
  std::vector<std::unique_ptr<PointInShell>> tests_;
};

}  // namespace

EnclosedParts FindEnclosedParts(const RawMesh& mesh, const std::vector<uint32_t>& shell_vertices) {
  EnclosedParts out;
  out.shell_sides.assign(shell_vertices.size(), -1);
  if (shell_vertices.empty() || mesh.num_faces() == 0) return out;
  Nesting nesting(mesh);
  if (nesting.seams()) return out;
  const std::vector<Component>& components = nesting.components();
  const uint32_t nc = static_cast<uint32_t>(components.size());
  std::vector<uint32_t> face_of_vertex(mesh.num_vertices(), UINT32_MAX);
  for (uint32_t c = 0; c < mesh.triangles.size(); ++c) face_of_vertex[mesh.triangles[c]] = c / 3;
  std::vector<int64_t> shell_of(nc, -1);  // component -> index into shell_vertices
  for (size_t s = 0; s < shell_vertices.size(); ++s) {
    const uint32_t v = shell_vertices[s];
    if (v < face_of_vertex.size() && face_of_vertex[v] != UINT32_MAX)
      shell_of[nesting.ComponentOf(face_of_vertex[v])] = static_cast<int64_t>(s);
  }

  // What lies inside each closed component, short of its children: a body's material (it
  // faces outward), a shared surface's inner body (it faces into itself, with a body's material
  // around it), or a cavity (any other surface facing into itself). Parents first.
  enum class Inside : uint8_t { kNothing, kBody, kInnerBody, kCavity };
  std::vector<Inside> inside(nc, Inside::kNothing);
  std::vector<uint32_t> order;  // roots first, then each component's children
  for (uint32_t c = 0; c < nc; ++c)
    if (components[c].closed && components[c].parent == kNoComponent) order.push_back(c);
  for (size_t i = 0; i < order.size(); ++i)
    for (const uint32_t child : components[order[i]].children) order.push_back(child);
  for (const uint32_t c : order) {
    const Component& k = components[c];
    const bool material_around =
        k.parent != kNoComponent &&
        (inside[k.parent] == Inside::kBody || inside[k.parent] == Inside::kInnerBody);
    if (k.six_volume > 0)
      inside[c] = material_around ? Inside::kNothing : Inside::kBody;  // kNothing: crossing
    else if (k.six_volume < 0)
      inside[c] = material_around && shell_of[c] >= 0 ? Inside::kInnerBody : Inside::kCavity;
  }
  // Parts only in the trees that hold an inner body, and none in a tree the orientation left
  // inconsistent (a body facing outward inside material).
  std::vector<int64_t> root_of(nc, kNoComponent);
  for (const uint32_t c : order)
    root_of[c] = components[c].parent == kNoComponent ? c : root_of[components[c].parent];
  std::vector<uint8_t> parted(nc, 0), broken(nc, 0);
  for (const uint32_t c : order) {
    parted[root_of[c]] |= inside[c] == Inside::kInnerBody;
    broken[root_of[c]] |= inside[c] == Inside::kNothing;
  }

  std::vector<FaceSides> face_sides(mesh.num_faces());
  std::vector<int32_t> part_of(nc, kSpace);
  std::vector<double> volumes;
  for (const uint32_t c : order) {
    if (!parted[root_of[c]] || broken[root_of[c]]) continue;
    const Component& k = components[c];
    if (inside[c] == Inside::kBody || inside[c] == Inside::kInnerBody) {
      part_of[c] = static_cast<int32_t>(volumes.size());
      double six_volume = std::fabs(k.six_volume);
      for (const uint32_t child : k.children) six_volume += components[child].six_volume;
      volumes.push_back(six_volume / 6.0);
    }
    const int32_t around = k.parent == kNoComponent ? kSpace : part_of[k.parent];
    FaceSides sides;
    if (k.six_volume > 0) {
      sides = {part_of[c], around, 0};
    } else {
      sides = {around, part_of[c], 0};
    }
    sides.weight = (sides.behind != kSpace) - (sides.ahead != kSpace);
    for (const uint32_t f : k.faces) face_sides[f] = sides;
    if (inside[c] == Inside::kInnerBody) out.shell_sides[shell_of[c]] = -2;  // indexed below
  }
  if (volumes.empty()) return out;

  SolidParts& parts = out.parts;
  parts.volumes = std::move(volumes);
  parts.face_sides.resize(face_sides.size());
  absl::flat_hash_map<std::tuple<int32_t, int32_t, int32_t>, uint32_t> index;
  for (size_t f = 0; f < face_sides.size(); ++f) {
    const FaceSides& s = face_sides[f];
    const auto [it, fresh] = index.try_emplace(std::tuple(s.behind, s.ahead, s.weight),
                                               static_cast<uint32_t>(parts.sides.size()));
    if (fresh) parts.sides.push_back(s);
    parts.face_sides[f] = it->second;
  }
  for (size_t s = 0; s < shell_vertices.size(); ++s)
    if (out.shell_sides[s] == -2)
      out.shell_sides[s] =
          static_cast<int32_t>(parts.face_sides[face_of_vertex[shell_vertices[s]]]);
  return out;
}

}  // namespace femsimp
