#include "engine/prepare.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <string>
#include <tuple>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "engine/enclosed_parts.h"
#include "engine/local_origin.h"
#include "engine/solid_parts.h"
#include "engine/spatial_order.h"

namespace femsimp {
namespace {

// How many seams and other leftover defects an error names one by one (the message goes into a
// gRPC status too, whose size is bounded).
constexpr size_t kMaxListed = 20;

// How many defects the repair left that Mesh::Build refuses (engine/repair.h, BlocksTheBuild).
size_t BlockingDefects(const RepairReport& report) {
  size_t n = 0;
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (BlocksTheBuild(static_cast<RepairKind>(k))) n += report.counts[k];
  return n;
}

// Those defects, named by their records.
absl::Status DefectsLeft(const RepairReport& report) {
  std::vector<std::string> listed;
  size_t defects = 0;
  for (const RepairRecord& r : report.records)
    if (BlocksTheBuild(r.kind) && defects++ < kMaxListed) listed.push_back(r.ToString());
  if (defects > kMaxListed) listed.push_back(absl::StrCat("and ", defects - kMaxListed, " more"));
  return absl::InvalidArgumentError(
      absl::StrCat("the mesh has defects no repair fixes: ", absl::StrJoin(listed, "; ")));
}

// The seams' ends in the curve order, ordered by (a, b) again.
void RenumberSeams(const std::vector<uint32_t>& new_id, std::vector<SeamEdge>& seams) {
  for (SeamEdge& seam : seams) {
    seam.a = new_id[seam.a];
    seam.b = new_id[seam.b];
    if (seam.a > seam.b) {
      std::swap(seam.a, seam.b);
      std::swap(seam.pa, seam.pb);
    }
  }
  std::sort(seams.begin(), seams.end(), [](const SeamEdge& x, const SeamEdge& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
}

// Where the rejoined output first differs from the input's seams: an edge by its ends' places.
std::string FirstSeamChange(const RawMesh& out, const RejoinReport& report) {
  const bool added = !report.new_seams.empty();
  if (!added && report.changed_seams.empty()) return "";
  const EdgeUse& e = added ? report.new_seams.front() : report.changed_seams.front();
  const auto place = [&](uint32_t input_vertex) -> std::string {
    for (size_t o = 0; o < report.input_vertex.size(); ++o)
      if (report.input_vertex[o] == input_vertex) {
        const std::array<double, 3> p = WorldPoint(out, o);
        return absl::StrFormat("(%g, %g, %g)", p[0], p[1], p[2]);
      }
    return "(gone)";
  };
  return absl::StrCat("; the first: ", added ? "a new" : "a changed", " edge from ", place(e.a),
                      " to ", place(e.b), " of ", e.faces, " faces");
}

// A shared surface the parts now bound: a change, no longer a defect left (its record, if the
// report kept one, says so).
void CountSharedWall(RepairReport& report, int64_t input_facet, size_t facets,
                     double inner_volume) {
  --report.counts[static_cast<size_t>(RepairKind::kSharedShellLeft)];
  ++report.counts[static_cast<size_t>(RepairKind::kSharedShell)];
  for (RepairRecord& r : report.records)
    if (r.kind == RepairKind::kSharedShellLeft && r.facet == input_facet) {
      r.kind = RepairKind::kSharedShell;
      r.detail = absl::StrFormat(
          "closed surface of %u facets inside another body, every facet of it written twice, "
          "facing both ways: the surface two bodies share (a body inside another: an insert, a "
          "core, a part under a coating); kept and simplified once, written once per body in "
          "the output; each body a part (the inner one's volume %.6g; a cavity's wall "
          "written twice reads the same: write it once to keep the cavity)",
          facets, inner_volume);
      break;
    }
  std::stable_sort(report.records.begin(), report.records.end(),
                   [](const RepairRecord& a, const RepairRecord& b) {
                     return std::tie(a.kind, a.facet, a.vertex) <
                            std::tie(b.kind, b.facet, b.vertex);
                   });
}

// A vertex of each surface two bodies share (RepairResult::shared_shells), in the repaired
// soup's numbering.
std::vector<uint32_t> SharedShellVertices(const RawMesh& raw, const RepairResult& repaired) {
  std::vector<uint32_t> vertices;
  for (const RepairResult::SharedShell& shell : repaired.shared_shells)
    vertices.push_back(shell.facet < raw.num_faces() ? raw.triangles[3 * shell.facet] : UINT32_MAX);
  return vertices;
}

// Parts for the bodies inside another that share their whole surface with it, where
// FindEnclosedParts can make them; the others stay cavity walls, reported as left.
std::vector<SharedWall> BoundSharedShells(RawMesh& raw, const std::vector<uint32_t>& vertices,
                                          const RepairResult& repaired, RepairReport& report) {
  EnclosedParts enclosed = FindEnclosedParts(raw, vertices);
  if (enclosed.parts.sides.empty()) return {};
  std::vector<SharedWall> walls;
  for (size_t s = 0; s < vertices.size(); ++s) {
    if (enclosed.shell_sides[s] < 0) continue;
    const uint32_t sides = static_cast<uint32_t>(enclosed.shell_sides[s]);
    const RepairResult::SharedShell& shell = repaired.shared_shells[s];
    walls.push_back({sides, shell.twin_groups});
    CountSharedWall(
        report, repaired.facet_origin[shell.facet],
        std::count(enclosed.parts.face_sides.begin(), enclosed.parts.face_sides.end(), sides),
        enclosed.parts.volumes[enclosed.parts.sides[sides].ahead]);
  }
  raw.face_sides = std::move(enclosed.parts.face_sides);
  raw.sides = std::move(enclosed.parts.sides);
  return walls;
}

// Appends each shared wall's faces turned over (the inner body's copy) with the group that copy
// had in the input.
void WriteWallsTwice(const Mesh& mesh, const std::vector<SharedWall>& walls, RawMesh& out) {
  const HalfEdgeQ* h = mesh.halfedges();
  std::vector<std::pair<uint32_t, const SharedWall*>> copies;  // output face, its wall
  uint32_t k = 0;
  for (uint32_t f = 0; f < mesh.face_capacity(); ++f) {
    if (mesh.IsFaceRemoved(f)) continue;
    const uint32_t sides = Mesh::SidesOf(h[3 * f]);
    for (const SharedWall& wall : walls)
      if (wall.sides == sides) copies.push_back({k, &wall});
    ++k;
  }
  const size_t faces = out.num_faces();
  const bool groups = std::any_of(walls.begin(), walls.end(),
                                  [](const SharedWall& w) { return !w.twin_groups.empty(); });
  if (groups && out.face_groups.empty()) out.face_groups.assign(faces, 0);  // all were 0
  out.triangles.reserve(3 * (faces + copies.size()));
  for (const auto& [c, wall] : copies) {
    const uint32_t a = out.triangles[3 * c], b = out.triangles[3 * c + 1],
                   d = out.triangles[3 * c + 2];
    out.triangles.insert(out.triangles.end(), {a, d, b});
    for (FaceField& field : out.face_fields) field.values.push_back(field.values[c]);
    if (out.face_groups.empty()) continue;
    uint32_t group = out.face_groups[c];
    for (const auto& [kept, twin] : wall->twin_groups)
      if (kept == group) {
        group = twin;
        break;
      }
    out.face_groups.push_back(group);
  }
}

}  // namespace

absl::StatusOr<PreparedMesh> PrepareMesh(RawMesh raw, const RepairOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  PrepareTimes times;
  const Clock::time_point repair_start = Clock::now();
  absl::StatusOr<RepairResult> repaired = RepairMesh(raw, options);
  if (!repaired.ok()) return repaired.status();
  if (BlockingDefects(repaired->report) > 0) return DefectsLeft(repaired->report);

  // Curve order for the kernel's memory walks (engine/spatial_order.h); the repair's report
  // keeps the input's facet and vertex ids.
  std::vector<uint32_t> shell_vertices;
  if (repaired->seams.empty()) shell_vertices = SharedShellVertices(raw, *repaired);
  const Clock::time_point order_start = Clock::now();
  const std::vector<uint32_t> new_id = SortSpatially(raw);
  times.order_seconds = seconds_since(order_start);
  if (!new_id.empty()) {
    RenumberSeams(new_id, repaired->seams);
    for (uint32_t& v : shell_vertices)
      if (v < new_id.size()) v = new_id[v];
  }

  // Parts of an assembly that share faces or edges: cut into manifold sheets along the seams,
  // whose vertices are locked and joined again by OutputMesh.
  // Their parts are solids: which part lies on each side of a face is found before the cut.
  SeamMap seam_map;
  if (!repaired->seams.empty()) {
    const EdgeGroups edges(raw.triangles);
    SolidParts parts = FindSolidParts(raw, &edges);
    raw.face_sides = std::move(parts.face_sides);
    raw.sides = std::move(parts.sides);
    absl::StatusOr<SeamMap> split = SplitSeams(raw, &edges);
    if (!split.ok()) return split.status();
    seam_map = *std::move(split);
  }
  // Bodies inside another sharing all their surface with it: parts too, without a seam.
  std::vector<SharedWall> shared_walls;
  if (!shell_vertices.empty())
    shared_walls = BoundSharedShells(raw, shell_vertices, *repaired, repaired->report);
  times.repair_seconds = seconds_since(repair_start) - times.order_seconds;
  const Clock::time_point build_start = Clock::now();
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  if (!mesh.ok()) return mesh.status();
  times.build_seconds = seconds_since(build_start);
  return PreparedMesh{*std::move(mesh),    std::move(repaired->report), std::move(repaired->seams),
                      std::move(seam_map), std::move(shared_walls),     times};
}

absl::StatusOr<RawMesh> OutputMesh(const Mesh& mesh, const SeamMap& seams,
                                   const std::vector<SharedWall>& walls) {
  if (!walls.empty()) {
    RawMesh out = mesh.ToRaw();
    WriteWallsTwice(mesh, walls, out);
    return out;
  }
  if (seams.empty()) return mesh.ToRaw();
  std::vector<uint32_t> ids;
  RawMesh out = mesh.ToRaw(&ids);
  absl::StatusOr<RejoinReport> rejoined = RejoinSeams(out, ids, seams);
  if (!rejoined.ok()) return rejoined.status();
  if (!rejoined->conforming())
    return absl::FailedPreconditionError(absl::StrCat(
        "the seams did not stay conforming (", rejoined->changed_seams.size(), " changed, ",
        rejoined->new_seams.size(), " new, ", rejoined->missing_seam_vertices,
        " seam vertices missing", FirstSeamChange(out, *rejoined),
        "): a bug of the engine, please report it with the input"));
  return out;
}

}  // namespace femsimp
