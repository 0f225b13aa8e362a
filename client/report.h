// What one simplify run reports (local or remote): the per-pass table, the summary and the
// --stats-json document.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "engine/repair.h"
#include "engine/simplify.h"
#include "fecheck/fe_check.h"

namespace femsimp::cli {

// The fidelity figures of SimplifyResult (docs/FIDELITY.md), local or from the server's Result.
struct FidelityFigures {
  uint64_t feature_edges = 0, corner_vertices = 0;
  double tolerance_abs = 0.0, deviation_bound = 0.0;
  double volume_change = 0.0, centroid_shift = 0.0, max_field_change = 0.0;
  MassSummary input_mass, output_mass;
  double inertia_change = 0.0;
  double wall_limited_share = 0.0, thinnest_wall = 0.0;  // the wall rule's set-up
  SoupCrossings output_crossings;
  CoordinatePrecision coordinates;
  std::vector<SimplifyResult::PartVolume> parts;  // of an assembly meeting at seams
  static FidelityFigures Of(const SimplifyResult& r);
};

struct RunReport {
  std::string input_path, output_path;
  SimplifyOptions options;
  uint64_t input_vertices = 0, input_faces = 0;
  uint64_t output_vertices = 0, output_faces = 0;
  double load_seconds = 0.0;    // read + validate the input (remote: read the file)
  double engine_seconds = 0.0;  // Simplify() alone
  double busy_seconds = 0.0;    // summed over contexts
  double write_seconds = 0.0;
  double crossings_seconds = 0.0;  // local: FindCrossings on the output (remote: the server's)
  double transfer_seconds = 0.0;   // remote: whole RPC, upload to last chunk
  double queue_seconds = 0.0;      // remote: waiting in the server's queue
  std::string stop_reason;
  std::string limiting_rule;   // the rule that refused most in the last pass (no_progress)
  std::string server, job_id;  // remote only
  int attempts = 0;            // remote only: calls made, retries included
  uint64_t modeled_cycles = 0;
  std::vector<PassStats> passes;
  FidelityFigures fidelity;
  // Face data of the input: distinct group ids (0: no groups) and field names; what
  // --drop-face-data left out of OUT (empty: nothing).
  uint64_t face_groups = 0;
  std::vector<std::string> face_fields;
  std::string dropped_face_data;
  // What the reader left out of IN (MSH: elements other than triangles), one line each.
  std::vector<std::string> input_warnings;
  // What OUT's format lost (binary STL of a part far from the origin: rounded corners).
  std::vector<std::string> output_warnings;
  // What the repair stage changed (local: PrepareMesh; remote: the server's Result); with
  // repair_details every record in the summary, else the first kSummaryRepairRecords.
  RepairReport repair;
  bool repair_details = false;
  // --fe-check: the FE check of the (repaired) input against the output, local or the server's.
  std::optional<fecheck::FeCheckReport> fe_check;
};

inline constexpr size_t kSummaryRepairRecords = 5;
// The summary warns when the tolerance is at least this share of a solid's mean thickness.
inline constexpr double kThinWallShare = 0.5;
// Records kept per kind for the summary and --stats-json (the counts are always complete).
inline constexpr size_t kReportRepairRecordsPerKind = 10000;

// Column header and one row per pass of the progress table (cache column for the cell back end).
std::string PassTableHeader(Backend backend);
std::string PassTableRow(const PassStats& p, Backend backend);
// The remote client's progress: one line redrawn in place ("\r" ... clear to the end), a bar
// toward the target, then the figures of the last pass. A run without a target ends when its
// passes stop removing, which nothing tells in advance: no bar.
std::string ProgressLine(const PassStats& p, uint64_t input_vertices, const SimplifyOptions& o);
// Vertices/faces in and out, timings, stop reason; several lines.
std::string Summary(const RunReport& r);
// The repair lines of the summary: the changes with the weld tolerance, one line per kind with
// its count, then up to max_records records (facet, coordinates, what changed).
std::string RepairSummary(const RepairReport& r, size_t max_records);
// The --stats-json document.
std::string ReportJson(const RunReport& r);
absl::Status WriteTextFile(const std::string& path, const std::string& text);

}  // namespace femsimp::cli
