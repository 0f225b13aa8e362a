#include "engine/solid_parts.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "engine/edge_groups.h"
#include "engine/union_find.h"
#include "engine/vec.h"

namespace femsimp {
namespace {

// Side 2f lies behind face f (against its normal), side 2f + 1 ahead of it.
uint32_t Behind(uint32_t f) { return 2 * f; }
uint32_t Ahead(uint32_t f) { return 2 * f + 1; }

DVec3 Point(const RawMesh& mesh, uint32_t v) {
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

DVec3 Unit(const DVec3& a) {
  const double n = Norm(a);
  return n > 0.0 ? (1.0 / n) * a : DVec3{0, 0, 0};
}

// Joins the sides that face each wedge of space between neighbouring faces around the edge of
// group g. Seen along the edge lo -> hi, a face's normal points counter-clockwise when the face
// runs lo -> hi, so the wedge counter-clockwise of a face lies ahead of it exactly then.
void JoinAroundSeam(const RawMesh& mesh, const EdgeGroups& edges, size_t g, UnionFind& sides) {
  const std::vector<uint32_t>& tri = mesh.triangles;
  const uint32_t first = edges.half[edges.begin[g]];
  const uint32_t lo = std::min(tri[first], tri[NextCorner(first)]);
  const uint32_t hi = std::max(tri[first], tri[NextCorner(first)]);
  const DVec3 origin = Point(mesh, lo);
  const DVec3 t = Unit(Point(mesh, hi) - origin);
  // Any two directions across the edge, with t = u x v.
  const DVec3 axis = std::fabs(t.x) < 0.6 ? DVec3{1, 0, 0} : DVec3{0, 1, 0};
  const DVec3 u = Unit(Cross(axis, t)), v = Cross(t, u);
  struct Around {
    double angle;
    uint32_t face;
    bool runs_up;  // lo -> hi
  };
  std::vector<Around> around;
  for (uint32_t i = edges.begin[g]; i < edges.begin[g + 1]; ++i) {
    const uint32_t h = edges.half[i];
    const uint32_t c = tri[NextCorner(NextCorner(h))];
    const DVec3 w = Point(mesh, c) - origin;
    const DVec3 across = w - Dot(w, t) * t;
    around.push_back({std::atan2(Dot(across, v), Dot(across, u)), h / 3, tri[h] == lo});
  }
  std::sort(around.begin(), around.end(), [](const Around& a, const Around& b) {
    return a.angle != b.angle ? a.angle < b.angle : a.face < b.face;
  });
  for (size_t i = 0; i < around.size(); ++i) {
    const Around& f = around[i];
    const Around& next = around[(i + 1) % around.size()];
    sides.Union(f.runs_up ? Ahead(f.face) : Behind(f.face),
                next.runs_up ? Behind(next.face) : Ahead(next.face));
  }
}

}  // namespace

DVec3 SoupCentre(const RawMesh& mesh) {
  const std::vector<uint32_t>& tri = mesh.triangles;
  DVec3 lo = Point(mesh, tri[0]), hi = lo;
  for (const uint32_t v : tri) {
    const DVec3 p = Point(mesh, v);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return 0.5 * (lo + hi);
}

SolidParts FindSolidParts(const RawMesh& mesh, const EdgeGroups* grouped) {
  const std::vector<uint32_t>& tri = mesh.triangles;
  const uint32_t nf = static_cast<uint32_t>(mesh.num_faces());
  std::optional<EdgeGroups> own;
  const EdgeGroups& edges = grouped != nullptr ? *grouped : own.emplace(tri);
  UnionFind sides(2 * size_t{nf});
  UnionFind pieces(nf);
  std::vector<uint8_t> seam_piece(nf, 0);  // set on one face of each piece with a seam
  for (size_t g = 0; g < edges.size(); ++g) {
    const uint32_t n = edges.count(g);
    const uint32_t h0 = edges.half[edges.begin[g]];
    if (n == 1) return {};  // open: space on both sides
    if (n == 2) {
      const uint32_t h1 = edges.half[edges.begin[g] + 1];
      const uint32_t f0 = h0 / 3, f1 = h1 / 3;
      pieces.Union(f0, f1);
      if (tri[h0] != tri[h1]) {  // opposite directions: an ordinary edge
        sides.Union(Ahead(f0), Ahead(f1));
        sides.Union(Behind(f0), Behind(f1));
        continue;
      }
    }
    for (uint32_t i = edges.begin[g]; i < edges.begin[g + 1]; ++i)
      pieces.Union(h0 / 3, edges.half[i] / 3);
    seam_piece[h0 / 3] = 1;
    JoinAroundSeam(mesh, edges, g, sides);
  }
  for (uint32_t f = 0; f < nf; ++f)
    if (seam_piece[f]) seam_piece[pieces.Find(f)] = 1;
  bool any_seam = false;
  for (uint32_t f = 0; f < nf; ++f) any_seam |= seam_piece[f] && pieces.Find(f) == f;
  if (!any_seam) return {};

  // Each region's signed volume: its sides' faces, with the normal pointing out of the region
  // (a face ahead of the region counts as it is, one behind it turned). Measured from a point
  // near the part so that no large terms cancel.
  const DVec3 centre = SoupCentre(mesh);
  absl::flat_hash_map<uint32_t, double> region_volume;
  for (uint32_t f = 0; f < nf; ++f) {
    if (!seam_piece[pieces.Find(f)]) continue;
    const uint32_t behind = sides.Find(Behind(f)), ahead = sides.Find(Ahead(f));
    if (behind == ahead) return {};  // a sheet that space reaches around
    const DVec3 a = Point(mesh, tri[3 * f]) - centre, b = Point(mesh, tri[3 * f + 1]) - centre,
                c = Point(mesh, tri[3 * f + 2]) - centre;
    const double volume = Dot(a, Cross(b, c)) / 6.0;
    region_volume[behind] += volume;
    region_volume[ahead] -= volume;
  }
  // Per piece, its unbounded region: the one of negative volume, which must be the only one.
  absl::flat_hash_map<uint32_t, uint32_t> unbounded;  // piece -> region
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t piece = pieces.Find(f);
    if (!seam_piece[piece]) continue;
    for (const uint32_t side : {Behind(f), Ahead(f)}) {
      const uint32_t region = sides.Find(side);
      const double volume = region_volume[region];
      if (volume > 0.0) continue;
      const auto [it, fresh] = unbounded.try_emplace(piece, region);
      if (!fresh && it->second != region) return {};  // two regions without a positive volume
    }
  }
  // A piece of no volume (flat sheets) may round every region's to a positive one.
  for (uint32_t f = 0; f < nf; ++f)
    if (seam_piece[f] && pieces.Find(f) == f && !unbounded.contains(f)) return {};

  SolidParts out;
  out.face_sides.resize(nf);
  absl::flat_hash_map<uint32_t, int32_t> part_of;  // region -> part
  const auto part = [&](uint32_t piece, uint32_t side) {
    const uint32_t region = sides.Find(side);
    if (unbounded.at(piece) == region) return kSpace;
    const auto [it, fresh] = part_of.try_emplace(region, static_cast<int32_t>(out.volumes.size()));
    if (fresh) out.volumes.push_back(region_volume[region]);
    return it->second;
  };
  absl::flat_hash_map<std::tuple<int32_t, int32_t, int32_t>, uint32_t> index;  // -> sides index
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t piece = pieces.Find(f);
    FaceSides s;  // a piece without a seam: oriented by the repair, weight +1
    if (seam_piece[piece]) {
      s.behind = part(piece, Behind(f));
      s.ahead = part(piece, Ahead(f));
      s.weight = (s.behind != kSpace) - (s.ahead != kSpace);
    }
    const auto [it, fresh] = index.try_emplace(std::tuple(s.behind, s.ahead, s.weight),
                                               static_cast<uint32_t>(out.sides.size()));
    if (fresh) out.sides.push_back(s);
    out.face_sides[f] = it->second;
  }
  return out;
}

}  // namespace femsimp
