// Independent judge of one simplification of a CAD-like part (issue 12, item 7): reads the input
// and the output mesh files and measures the output from the two triangle soups alone, with the
// CGAL judge (tests/judge) and a CGAL count of self-intersecting face pairs. Nothing here goes
// through the engine.
//
//   cad_judge IN OUT [--tolerance-relative F] [--max-volume-change F] [--repaired-input]
//
// Prints one JSON object on stdout (figures, then "failures": the checks that did not hold) and
// exits 0 when every check holds, 1 when one fails, 2 on a usage or read error. Checks:
//   - topology kept: Euler characteristic, components, boundary edges present or not, boundary
//     loops, non-manifold edges/vertices and misoriented edges (none more than the input has);
//   - no new self-intersection: the output has no more intersecting face pairs than the input
//     (so none at all for an input without any); faces that meet at a vertex, or at vertices at
//     exactly one place, touch there and do not count;
//   - two-sided Hausdorff distance <= F * diagonal + float storage slack (when F > 0); the judge's
//     figure is a certified lower bound within 1 % of the tolerance (judge.h);
//   - |volume change| <= bound + float slack on closed inputs (when the bound is > 0);
//   - face groups: the output has the same group ids as the input;
//   - seams (non-manifold edges of an assembly): the output's are the input's simplified along
//     themselves, junctions and curve ends kept (seam_conformity.h; not judged with
//     --repaired-input).
// --repaired-input: IN is a broken soup that femsimp repaired before simplifying (cracks stitched,
// non-manifold vertices split): the figures the repair changes by design (Euler characteristic,
// components, boundary edges and loops) are reported but not judged; everything else is.

#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "engine/io/mesh_io.h"
#include "engine/local_origin.h"
#include "tests/judge/judge.h"
#include "tests/judge/seam_conformity.h"

namespace femsimp {
namespace {

struct Measured {
  judge::Topology topology;
  long self_intersecting_pairs = 0;
  long overlapping_pairs = 0;  // in one plane, no corner in common (bodies exported apart)
  double volume = 0.0, area = 0.0;
  size_t groups = 0;
};

// The mesh with the vertices that lie at exactly one place named by one index, and whether any
// did. Faces that meet at such a place touch there, as at a shared vertex: repair gives each fan
// of a non-manifold vertex a copy of its own, at the same place, and a soup may hold parts that
// touch at a vertex each writes itself.
std::pair<RawMesh, bool> CoincidentVerticesShared(const RawMesh& mesh) {
  RawMesh shared = mesh;
  absl::flat_hash_map<std::array<uint32_t, 3>, uint32_t> first;  // bits of x, y, z
  std::vector<uint32_t> index(mesh.num_vertices());
  bool any = false;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    std::array<uint32_t, 3> at;
    for (int i = 0; i < 3; ++i)  // + 0.0f: -0 and +0 are one place
      at[i] = std::bit_cast<uint32_t>(mesh.positions[3 * v + i] + 0.0f);
    index[v] = first.try_emplace(at, v).first->second;
    any |= index[v] != v;
  }
  for (uint32_t& corner : shared.triangles) corner = index[corner];
  return {std::move(shared), any};
}

Measured Measure(const RawMesh& mesh) {
  Measured m;
  m.topology = judge::ComputeTopology(mesh);
  // An assembly's parts share their seams' vertices, and vertices at one place are one corner:
  // the mesh test would split them into copies that touch, and count every touch.
  const auto [shared, coincident] = CoincidentVerticesShared(mesh);
  const bool seams = m.topology.nonmanifold_edges > 0 || m.topology.nonmanifold_vertices > 0;
  m.self_intersecting_pairs =
      static_cast<long>(seams || coincident ? judge::SoupSelfIntersectingPairs(shared)
                                            : judge::SelfIntersectingPairs(mesh));
  m.overlapping_pairs = static_cast<long>(judge::SoupOverlappingPairs(mesh));
  if (m.topology.closed_manifold()) m.volume = judge::SolidProperties(mesh).volume;
  m.area = judge::SurfaceProperties(mesh).area;
  m.groups = judge::GroupIds(mesh).size();
  return m;
}

std::string TopologyJson(const judge::Topology& t) {
  return absl::StrCat(R"({"vertices":)", t.vertices, R"(,"faces":)", t.faces, R"(,"euler":)",
                      t.euler(), R"(,"components":)", t.components, R"(,"boundary_edges":)",
                      t.boundary_edges, R"(,"boundary_loops":)", t.boundary_loops,
                      R"(,"nonmanifold_edges":)", t.nonmanifold_edges,
                      R"(,"nonmanifold_vertices":)", t.nonmanifold_vertices,
                      R"(,"misoriented_edges":)", t.misoriented_edges, "}");
}

std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

int Usage() {
  std::fprintf(stderr,
               "usage: cad_judge IN OUT [--tolerance-relative F] [--max-volume-change F] "
               "[--repaired-input]\n");
  return 2;
}

int Main(int argc, char** argv) {
  std::vector<std::string> files;
  double tolerance_relative = 0.0, max_volume_change = 0.0;
  bool repaired_input = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repaired-input") {
      repaired_input = true;
    } else if (arg == "--tolerance-relative" || arg == "--max-volume-change") {
      if (i + 1 >= argc) return Usage();
      double value;
      if (!absl::SimpleAtod(argv[++i], &value) || value < 0) return Usage();
      (arg == "--tolerance-relative" ? tolerance_relative : max_volume_change) = value;
    } else if (!arg.empty() && arg[0] == '-') {
      return Usage();
    } else {
      files.push_back(arg);
    }
  }
  if (files.size() != 2) return Usage();
  absl::StatusOr<RawMesh> in = ReadMeshFile(files[0]), out = ReadMeshFile(files[1]);
  for (const auto* r : {&in, &out}) {
    if (!r->ok()) {
      std::fprintf(stderr, "cad_judge: %s\n", std::string(r->status().message()).c_str());
      return 2;
    }
  }
  // Compared where the input's positions are measured from (each file has its own origin).
  ChangeOrigin(&*out, in->origin);
  const auto start = std::chrono::steady_clock::now();
  const Measured a = Measure(*in), b = Measure(*out);
  const double diag = judge::BoundingBoxDiagonal(*in);
  const double slack = judge::FloatStorageSlack(*in);
  std::vector<std::string> failures;
  auto check = [&](bool ok, const std::string& what) {
    if (!ok) failures.push_back(what);
  };

  // Topology.
  const judge::Topology &ta = a.topology, &tb = b.topology;
  check(repaired_input || tb.euler() == ta.euler(),
        absl::StrCat("Euler characteristic ", ta.euler(), " -> ", tb.euler()));
  check(repaired_input || tb.components == ta.components,
        absl::StrCat("components ", ta.components, " -> ", tb.components));
  check(repaired_input || (tb.boundary_edges == 0) == (ta.boundary_edges == 0),
        absl::StrCat("boundary edges ", ta.boundary_edges, " -> ", tb.boundary_edges));
  check(repaired_input || tb.boundary_loops == ta.boundary_loops,
        absl::StrCat("boundary loops ", ta.boundary_loops, " -> ", tb.boundary_loops));
  check(tb.nonmanifold_edges <= ta.nonmanifold_edges,
        absl::StrCat("non-manifold edges ", ta.nonmanifold_edges, " -> ", tb.nonmanifold_edges));
  check(tb.nonmanifold_vertices <= ta.nonmanifold_vertices,
        absl::StrCat("non-manifold vertices ", ta.nonmanifold_vertices, " -> ",
                     tb.nonmanifold_vertices));
  check(tb.misoriented_edges <= ta.misoriented_edges,
        absl::StrCat("misoriented edges ", ta.misoriented_edges, " -> ", tb.misoriented_edges));
  check(b.self_intersecting_pairs <= a.self_intersecting_pairs,
        absl::StrCat("self-intersecting face pairs ", a.self_intersecting_pairs, " -> ",
                     b.self_intersecting_pairs));
  check(b.groups == a.groups, absl::StrCat("face groups ", a.groups, " -> ", b.groups));
  // Assemblies: the seams conform, simplified along themselves only (a repaired soup's seams
  // are what the repair made of them: welds and removed facets change them by design).
  const judge::SeamConformity seams = judge::CheckSeamConformity(*in, *out);
  for (const std::string& problem : seams.problems) check(repaired_input, problem);

  // Hausdorff: measured with the error the fidelity tests use (1 % of the tolerance), or
  // 1e-4 of the diagonal when no tolerance is given.
  const double tolerance = tolerance_relative * diag;
  const judge::Hausdorff h = judge::HausdorffDistance(
      *in, *out, tolerance > 0 ? judge::HausdorffErrorFor(tolerance) : 1e-4 * diag);
  if (tolerance > 0) {
    check(h.a_to_b <= tolerance + slack,
          absl::StrCat("Hausdorff input->output ", h.a_to_b, " > tolerance ", tolerance));
    check(h.b_to_a <= tolerance + slack,
          absl::StrCat("Hausdorff output->input ", h.b_to_a, " > tolerance ", tolerance));
  }

  // Volume, on closed inputs: moving every vertex by the float slack sweeps at most
  // area * slack of volume.
  const bool closed = ta.closed_manifold();
  double volume_change = 0.0;
  if (closed && a.volume != 0.0) {
    volume_change = (b.volume - a.volume) / std::abs(a.volume);
    if (max_volume_change > 0) {
      const double volume_slack = a.area * slack / std::abs(a.volume);
      check(std::abs(volume_change) <= max_volume_change + volume_slack,
            absl::StrCat("volume change ", volume_change, " beyond ", max_volume_change));
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<std::string> quoted;
  for (const std::string& f : failures) quoted.push_back(Quoted(f));
  std::printf(
      "{\"input\":%s,\"output\":%s,\"diagonal\":%.9g,\"tolerance\":%.9g,\"slack\":%.3g,"
      "\"hausdorff_in_out\":%.9g,\"hausdorff_out_in\":%.9g,\"hausdorff\":%.9g,"
      "\"hausdorff_error\":%.3g,\"hausdorff_over_diagonal\":%.6g,\"closed\":%s,"
      "\"volume_in\":%.9g,\"volume_out\":%.9g,\"volume_change\":%.6g,"
      "\"self_intersections_in\":%ld,\"self_intersections_out\":%ld,"
      "\"overlaps_in\":%ld,\"overlaps_out\":%ld,\"groups_in\":%zu,"
      "\"groups_out\":%zu,\"seam_points_in\":%zu,\"seam_points_out\":%zu,"
      "\"vertex_reduction\":%.6g,\"judge_seconds\":%.3f,\"failures\":[%s]}\n",
      TopologyJson(ta).c_str(), TopologyJson(tb).c_str(), diag, tolerance, slack, h.a_to_b,
      h.b_to_a, h.two_sided(), h.error, diag > 0 ? h.two_sided() / diag : 0.0,
      closed ? "true" : "false", a.volume, b.volume, volume_change, a.self_intersecting_pairs,
      b.self_intersecting_pairs, a.overlapping_pairs, b.overlapping_pairs, a.groups, b.groups,
      seams.input_points, seams.output_points,
      ta.vertices > 0 ? 1.0 - static_cast<double>(tb.vertices) / ta.vertices : 0.0, seconds,
      absl::StrJoin(quoted, ",").c_str());
  for (const std::string& f : failures) std::fprintf(stderr, "cad_judge: FAILED: %s\n", f.c_str());
  return failures.empty() ? 0 : 1;
}

}  // namespace
}  // namespace femsimp

int main(int argc, char** argv) { return femsimp::Main(argc, argv); }
