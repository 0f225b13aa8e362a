#include "engine/prepare.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
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
  const Clock::time_point order_start = Clock::now();
  const std::vector<uint32_t> new_id = SortSpatially(raw);
  times.order_seconds = seconds_since(order_start);
  if (!new_id.empty()) RenumberSeams(new_id, repaired->seams);

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
  times.repair_seconds = seconds_since(repair_start) - times.order_seconds;
  const Clock::time_point build_start = Clock::now();
  absl::StatusOr<Mesh> mesh = Mesh::Build(raw);
  if (!mesh.ok()) return mesh.status();
  times.build_seconds = seconds_since(build_start);
  return PreparedMesh{*std::move(mesh), std::move(repaired->report), std::move(repaired->seams),
                      std::move(seam_map), times};
}

absl::StatusOr<RawMesh> OutputMesh(const Mesh& mesh, const SeamMap& seams) {
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
