#include "fecheck/tet_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/crossings.h"
#include "engine/mesh_checks.h"
#include "engine/point_in_shell.h"
#include "engine/union_find.h"
#include "engine/vec.h"

namespace femsimp::fecheck {
namespace {

// Six times the signed volume enclosed by the surface (divergence theorem, in double).
double SixVolume(const RawMesh& m) {
  double sum = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    const float* a = &m.positions[3 * m.triangles[3 * f]];
    const float* b = &m.positions[3 * m.triangles[3 * f + 1]];
    const float* c = &m.positions[3 * m.triangles[3 * f + 2]];
    sum += double{a[0]} * (double{b[1]} * c[2] - double{b[2]} * c[1]) -
           double{a[1]} * (double{b[0]} * c[2] - double{b[2]} * c[0]) +
           double{a[2]} * (double{b[0]} * c[1] - double{b[1]} * c[0]);
  }
  return sum;
}

DVec3 Corner(const RawMesh& m, size_t f, int k) {
  const float* p = &m.positions[3 * size_t(m.triangles[3 * f + k])];
  return {p[0], p[1], p[2]};
}

// The surface's vertex-connected parts, in a fixed order (the hole list and the bodies are the
// same every run): each with its faces, six times its signed volume (negative for a cavity's
// wall, which faces into the cavity) and a probe point a thousandth of its largest facet's size
// off that facet, on the side the facet faces: in the region next to it, short of any other.
struct SurfacePart {
  std::vector<uint32_t> faces;
  double six_volume = 0;
  double largest_twice_area = 0;  // 0: every facet degenerate, no probe
  DVec3 probe{};
};

std::vector<SurfacePart> PartsOf(const RawMesh& m) {
  const size_t nf = m.num_faces();
  UnionFind vertices(uint32_t(m.num_vertices()));
  for (size_t f = 0; f < nf; ++f)
    for (int k = 1; k < 3; ++k) vertices.Union(m.triangles[3 * f], m.triangles[3 * f + k]);
  std::map<uint32_t, SurfacePart> by_root;
  std::map<uint32_t, size_t> largest_facet;
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t root = vertices.Find(m.triangles[3 * f]);
    SurfacePart& part = by_root[root];
    part.faces.push_back(static_cast<uint32_t>(f));
    const DVec3 a = Corner(m, f, 0), b = Corner(m, f, 1), c = Corner(m, f, 2);
    part.six_volume += Dot(a, Cross(b, c));
    const double twice_area = Norm(Cross(b - a, c - a));
    if (twice_area > part.largest_twice_area)
      part.largest_twice_area = twice_area, largest_facet[root] = f;
  }
  std::vector<SurfacePart> parts;
  parts.reserve(by_root.size());
  for (auto& [root, part] : by_root) {
    if (part.largest_twice_area > 0) {
      const size_t f = largest_facet[root];
      const DVec3 a = Corner(m, f, 0), b = Corner(m, f, 1), c = Corner(m, f, 2);
      part.probe = (1.0 / 3) * (a + b + c) +
                   (1e-3 / std::sqrt(part.largest_twice_area)) * Cross(b - a, c - a);
    }
    parts.push_back(std::move(part));
  }
  return parts;
}

// A point in each cavity of the solid, for tetgen's hole list: tetgen meshes every region the
// surface encloses, a cavity too, unless it holds a hole point. A cavity wall's probe lies in
// the cavity where the surface's winding number is 0 there (outside the material).
std::vector<DVec3> CavityPoints(const RawMesh& m) {
  std::vector<DVec3> points;
  const PointInShell material(m.positions.data(), m.triangles);
  for (const SurfacePart& part : PartsOf(m))
    if (part.six_volume < 0 && part.largest_twice_area > 0 && material.Winding(part.probe) == 0)
      points.push_back(part.probe);
  return points;
}

// TetGen's surface format: nodes, then one facet per triangle (0-based, as -z reads them back),
// then a hole point in each cavity.
absl::Status WriteSmesh(const std::string& path, const RawMesh& m) {
  std::FILE* out = std::fopen(path.c_str(), "w");
  if (out == nullptr) return absl::InternalError(absl::StrCat("cannot write ", path));
  std::fprintf(out, "%zu 3 0 0\n", m.num_vertices());
  for (size_t v = 0; v < m.num_vertices(); ++v)  // %.9g: floats survive the round trip
    std::fprintf(out, "%zu %.9g %.9g %.9g\n", v, m.positions[3 * v], m.positions[3 * v + 1],
                 m.positions[3 * v + 2]);
  std::fprintf(out, "%zu 0\n", m.num_faces());
  for (size_t f = 0; f < m.num_faces(); ++f)
    std::fprintf(out, "3 %u %u %u\n", m.triangles[3 * f], m.triangles[3 * f + 1],
                 m.triangles[3 * f + 2]);
  const std::vector<DVec3> holes = CavityPoints(m);
  std::fprintf(out, "%zu\n", holes.size());
  for (size_t h = 0; h < holes.size(); ++h)
    std::fprintf(out, "%zu %.17g %.17g %.17g\n", h, holes[h].x, holes[h].y, holes[h].z);
  std::fprintf(out, "0\n");
  const bool ok = std::ferror(out) == 0;
  if (std::fclose(out) != 0 || !ok) return absl::InternalError(absl::StrCat("cannot write ", path));
  return absl::OkStatus();
}

// The surface split into bodies, each meshed on its own where bodies touch without sharing
// faces (tetgen refuses their overlapping facets): a body is a vertex-connected part of
// positive volume with the cavity walls (parts of negative volume) whose probes lie in it, the
// innermost such body. Vertices keep their positions; each body numbers its own from 0.
std::vector<RawMesh> Bodies(const RawMesh& m) {
  const auto soup_of = [&](const std::vector<uint32_t>& faces) {
    RawMesh body;
    body.origin = m.origin;
    std::map<uint32_t, uint32_t> renumbered;
    for (uint32_t f : faces)
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = m.triangles[3 * size_t{f} + k];
        const auto [at, fresh] = renumbered.try_emplace(v, uint32_t(renumbered.size()));
        if (fresh)
          body.positions.insert(body.positions.end(), &m.positions[3 * size_t{v}],
                                &m.positions[3 * size_t{v}] + 3);
        body.triangles.push_back(at->second);
      }
    return body;
  };
  const std::vector<SurfacePart> parts = PartsOf(m);
  std::vector<std::vector<uint32_t>> body_faces;
  std::vector<RawMesh> shells;
  std::vector<double> shell_volume;
  for (const SurfacePart& part : parts)
    if (part.six_volume > 0) {
      body_faces.push_back(part.faces);
      shells.push_back(soup_of(part.faces));
      shell_volume.push_back(part.six_volume);
    }
  std::vector<PointInShell> inside;  // each shell's test built once, for every cavity wall
  inside.reserve(shells.size());
  for (const RawMesh& shell : shells) inside.emplace_back(shell.positions.data(), shell.triangles);
  for (const SurfacePart& part : parts) {
    if (part.six_volume > 0) continue;
    // The wall's probe lies in the cavity of the innermost shell around it (a body in another's
    // cavity may have a cavity too), or in no shell where it is a body turned inside out.
    size_t holder = shells.size();
    for (size_t b = 0; b < shells.size() && part.largest_twice_area > 0; ++b)
      if (inside[b].Winding(part.probe) != 0 &&
          (holder == shells.size() || shell_volume[b] < shell_volume[holder]))
        holder = b;
    if (holder < shells.size())
      body_faces[holder].insert(body_faces[holder].end(), part.faces.begin(), part.faces.end());
    else
      body_faces.push_back(part.faces);  // inside out and in no body: CheckClosedSolid refuses it
  }
  std::vector<RawMesh> bodies;
  for (const std::vector<uint32_t>& faces : body_faces) bodies.push_back(soup_of(faces));
  return bodies;
}

int CountComponents(const TetMesh& mesh) {
  UnionFind parts(mesh.num_nodes());
  std::vector<bool> used(mesh.num_nodes(), false);
  for (size_t t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) {
      used[mesh.tets[4 * t + k]] = true;
      if (k > 0) parts.Union(mesh.tets[4 * t], mesh.tets[4 * t + k]);
    }
  int components = 0;
  for (uint32_t n = 0; n < mesh.num_nodes(); ++n)
    if (used[n] && parts.Find(n) == n) ++components;
  return components;
}

// The surface without the facets written twice facing both ways, or nothing where none is. Such
// a surface is one two bodies share, written once per body (femsimp's output of a body inside
// another): without it the two are one solid, which tetgen meshes whole, bonded, one material.
// Vertices only those facets used go too.
std::optional<RawMesh> WithoutSharedWalls(const RawMesh& m) {
  const auto key = [&](size_t f, bool turned) {
    const uint32_t* t = &m.triangles[3 * f];
    std::array<uint32_t, 3> k = {t[0], turned ? t[2] : t[1], turned ? t[1] : t[2]};
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    return k;
  };
  std::set<std::array<uint32_t, 3>> facets;
  for (size_t f = 0; f < m.num_faces(); ++f) facets.insert(key(f, false));
  std::vector<uint32_t> kept;
  for (size_t f = 0; f < m.num_faces(); ++f)
    if (!facets.contains(key(f, true))) kept.push_back(static_cast<uint32_t>(f));
  if (kept.size() == m.num_faces()) return std::nullopt;
  RawMesh out;
  out.origin = m.origin;
  std::vector<uint32_t> renumbered(m.num_vertices(), UINT32_MAX);
  for (const uint32_t f : kept)
    for (int k = 0; k < 3; ++k) {
      uint32_t& v = renumbered[m.triangles[3 * size_t{f} + k]];
      if (v == UINT32_MAX) {
        v = static_cast<uint32_t>(out.num_vertices());
        const float* p = &m.positions[3 * size_t{m.triangles[3 * size_t{f} + k]}];
        out.positions.insert(out.positions.end(), p, p + 3);
      }
      out.triangles.push_back(v);
    }
  return out;
}

}  // namespace

absl::Status CheckClosedSolid(const RawMesh& given) {
  const std::optional<RawMesh> bonded = WithoutSharedWalls(given);
  const RawMesh& surface = bonded ? *bonded : given;
  if (absl::Status s = CheckSoup(surface); !s.ok()) return s;
  const SoupTopology topology = TopologyOf(surface);
  if (topology.boundary_edges > 0)
    return absl::InvalidArgumentError(
        absl::StrCat("the surface is not closed (", topology.boundary_edges,
                     " boundary edges): an FE check needs a closed solid"));
  if (SixVolume(surface) <= 0)
    return absl::InvalidArgumentError(
        "the surface encloses no positive volume (is it oriented inwards?): an FE check needs a "
        "closed solid with its faces counter-clockwise seen from outside");
  // tetgen aborts on such a surface, quoting two of its own face numbers; this names the
  // surface's faces and where they cross, before any tool runs.
  const SoupCrossings c = FindCrossings(surface);
  if (c.pairs > 0)
    return absl::InvalidArgumentError(absl::StrCat(
        "the surface intersects itself: ", DescribeCrossings(c),
        ", so it bounds no solid and tetgen cannot mesh it (a finer export of the part avoids "
        "it)"));
  if (c.folds.pairs > 0)
    return absl::InvalidArgumentError(absl::StrCat(
        "the surface has folded faces: ", DescribeFolds(c),
        "; tetgen cannot mesh faces lying on each other (femsimp's repair unfolds those a flip "
        "of their edge undoes; its report's fold_left says why it left these)"));
  if (c.overlaps.pairs == 0) return absl::OkStatus();
  // Bodies that only touch are meshed each on its own (Tetrahedralise); faces overlapping within
  // one body are a fold no mesher takes.
  const std::vector<RawMesh> bodies = Bodies(surface);
  for (const RawMesh& body : bodies)
    if (SixVolume(body) <= 0)
      return absl::InvalidArgumentError(
          "the surface has touching bodies, one of which encloses no positive volume (is it "
          "oriented inwards?): an FE check needs each closed solid with its faces "
          "counter-clockwise seen from outside");
  bool apart = bodies.size() > 1;
  for (size_t b = 0; apart && b < bodies.size(); ++b)
    apart = FindCrossings(bodies[b]).overlaps.pairs == 0;
  if (apart) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat("the surface has overlapping faces, some within one body (parts joined by "
                   "shared vertices, which tetgen meshes whole): ",
                   DescribeOverlaps(c), "; tetgen cannot mesh overlapping faces"));
}

absl::StatusOr<std::vector<std::vector<double>>> ReadTetgenTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) return absl::InvalidArgumentError(absl::StrCat("cannot read ", path));
  std::vector<std::vector<double>> rows;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    std::vector<double> row;
    const char* p = line.c_str();
    for (;;) {
      while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
      if (*p == '\0') break;
      char* end = nullptr;
      const double x = std::strtod(p, &end);
      if (end == p || !std::isfinite(x))
        return absl::InvalidArgumentError(absl::StrCat(path, " line ", number, ": not a number"));
      row.push_back(x);
      p = end;
    }
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

namespace {

// tetgen on one surface written as run.dir/STEM.smesh, its nodes appended to `mesh` (scaled) and
// its tetrahedra after them, each of positive volume.
absl::Status AppendTetgenMesh(const RawMesh& surface, const std::string& stem, double unit_scale,
                              double max_tet_volume, bool keep_surface, const ToolRun& run,
                              TetMesh& mesh) {
  const std::string smesh = stem + ".smesh";
  if (absl::Status s = WriteSmesh(run.dir + "/" + smesh, surface); !s.ok()) return s;
  // -p: the surface is a piecewise linear complex; -Y: keep it as given; -q1.414: radius-edge
  // ratio bound (no slivers inside); -z: number from 0, as the .smesh does.
  std::string switches = keep_surface ? "-pq1.414Yz" : "-pq1.414z";
  if (max_tet_volume > 0) absl::StrAppend(&switches, absl::StrFormat("a%.9g", max_tet_volume));
  absl::StatusOr<ToolExit> ran = RunTool(kTetgen, {switches, smesh}, run);
  if (!ran.ok()) return ran.status();
  if (!ran->exit.ok()) return absl::InvalidArgumentError(ToolFailure(kTetgen, *ran));

  const std::string node_file = stem + ".1.node", ele_file = stem + ".1.ele";
  absl::StatusOr<std::vector<std::vector<double>>> nodes =
      ReadTetgenTable(run.dir + "/" + node_file);
  absl::StatusOr<std::vector<std::vector<double>>> tets = ReadTetgenTable(run.dir + "/" + ele_file);
  if (!nodes.ok() || !tets.ok() || tets->size() < 2)
    return absl::InvalidArgumentError(ToolFailure(kTetgen, *ran, "it made no tetrahedra"));
  const size_t first_node = mesh.num_nodes();
  const size_t num_nodes = nodes->size() - 1;
  mesh.nodes.reserve(3 * (first_node + num_nodes));
  for (size_t n = 1; n < nodes->size(); ++n) {
    const std::vector<double>& row = (*nodes)[n];
    if (row.size() < 4 || row[0] != static_cast<double>(n - 1))
      return absl::InternalError(
          absl::StrCat("tetgen's ", node_file, ": node ", n - 1, " malformed"));
    for (int k = 1; k <= 3; ++k) mesh.nodes.push_back(row[k] * unit_scale);
  }
  mesh.tets.reserve(mesh.tets.size() + 4 * (tets->size() - 1));
  for (size_t t = 1; t < tets->size(); ++t) {
    const std::vector<double>& row = (*tets)[t];
    if (row.size() < 5)
      return absl::InternalError(absl::StrCat("tetgen's ", ele_file, ": tetrahedron ", t - 1,
                                              " has fewer than four nodes"));
    uint32_t v[4];
    for (int k = 0; k < 4; ++k) {
      if (row[k + 1] < 0 || row[k + 1] >= static_cast<double>(num_nodes))
        return absl::InternalError(absl::StrCat("tetgen's ", ele_file, ": tetrahedron ", t - 1,
                                                " names a node out of range"));
      v[k] = static_cast<uint32_t>(first_node + static_cast<size_t>(row[k + 1]));
    }
    // Positive volume, as CalculiX's C3D10 numbering expects.
    const double* a = &mesh.nodes[3 * v[0]];
    double e[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e[i][k] = mesh.nodes[3 * v[i + 1] + k] - a[k];
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (det < 0) std::swap(v[1], v[2]);
    mesh.tets.insert(mesh.tets.end(), v, v + 4);
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<TetMesh> Tetrahedralise(const RawMesh& given, double unit_scale,
                                       double max_tet_volume, bool keep_surface,
                                       const ToolRun& run) {
  const std::optional<RawMesh> bonded = WithoutSharedWalls(given);
  const RawMesh& surface = bonded ? *bonded : given;
  TetMesh mesh;
  // Bodies that touch without sharing faces (CheckClosedSolid let them through) are meshed each
  // on its own: not bonded, their contacts carry no load.
  if (FindCrossings(surface).overlaps.pairs > 0) {
    const std::vector<RawMesh> bodies = Bodies(surface);
    for (size_t b = 0; b < bodies.size(); ++b)
      if (absl::Status s = AppendTetgenMesh(bodies[b], absl::StrCat("body", b), unit_scale,
                                            max_tet_volume, keep_surface, run, mesh);
          !s.ok())
        return s;
    mesh.bodies_meshed_apart = static_cast<int>(bodies.size());
  } else if (absl::Status s = AppendTetgenMesh(surface, "surface", unit_scale, max_tet_volume,
                                               keep_surface, run, mesh);
             !s.ok()) {
    return s;
  }
  mesh.components = CountComponents(mesh);
  return mesh;
}

}  // namespace femsimp::fecheck
