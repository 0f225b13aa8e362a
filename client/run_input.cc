#include "client/run_input.h"
#include "common/escape.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_set>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_replace.h"
#include "client/exit_codes.h"
#include "engine/io/mesh_io.h"
#include "engine/io/msh.h"

namespace femsimp::cli {

RunReport StartReport(const SimplifyArgs& args) {
  RunReport report;
  report.input_path = args.input;
  report.output_path = args.output;
  report.options = args.options;
  report.server = args.server;
  report.repair_details = args.repair_details;
  return report;
}

std::optional<RawMesh> ReadInput(const SimplifyArgs& args, RunReport& report,
                                 GroupNames* group_names) {
  absl::StatusOr<RawMesh> raw = ReadMeshFile(args.input, group_names, &report.input_warnings);
  if (!raw.ok()) {
    // Escaped before the %s: a NUL byte the reader quotes from the file would cut the message
    // there, losing the line it names.
    PrintError("femsimp: cannot read %s: %s\n", args.input.c_str(),
               EscapeControlCharacters(std::string(raw.status().message())).c_str());
    return std::nullopt;
  }
  report.input_vertices = raw->num_vertices();
  report.input_faces = raw->num_faces();
  if (HasFaceGroups(*raw))
    report.face_groups =
        std::unordered_set<uint32_t>(raw->face_groups.begin(), raw->face_groups.end()).size();
  for (const FaceField& field : raw->face_fields) report.face_fields.push_back(field.name);
  return *std::move(raw);
}

bool CheckOutputFormat(const SimplifyArgs& args, const RawMesh& input,
                       const GroupNames& group_names, RunReport& report) {
  const std::string ext = MeshFileExtension(args.output);
  // The names are checked on the input's groups: the output's are a subset.
  if (absl::Status names = CheckMshGroupNames(input, group_names); ext == ".msh" && !names.ok()) {
    PrintError("femsimp: cannot write %s: %s\n", args.output.c_str(),
               std::string(names.message()).c_str());
    return false;
  }
  absl::Status holds = CheckFormatHolds(ext, input);
  if (holds.ok()) return true;
  if (!args.drop_face_data) {
    PrintError("femsimp: cannot write %s: %s, or pass --drop-face-data\n", args.output.c_str(),
               std::string(holds.message()).c_str());
    return false;
  }
  // What the output will lack: what the format drops of a stand-in for the input's face data.
  RawMesh probe;
  if (HasFaceGroups(input)) probe.face_groups = {1};
  for (const FaceField& field : input.face_fields) probe.face_fields.push_back({field.name, {}});
  DropUnheldFaceData(ext, &probe);
  const bool groups_lost = HasFaceGroups(input) && probe.face_groups.empty();
  const bool fields_lost = !input.face_fields.empty() && probe.face_fields.empty();
  report.dropped_face_data = groups_lost ? "face groups" : "";
  if (fields_lost)
    absl::StrAppend(&report.dropped_face_data, groups_lost ? " and " : "", "face fields");
  PrintError("femsimp: note: %s will not hold the input's %s (--drop-face-data)\n",
             args.output.c_str(), report.dropped_face_data.c_str());
  return true;
}

namespace {

// Binary STL holds absolute floats: a part far from the origin rounds there, which the formats
// that keep its origin's digits do not.
std::string OutputRoundingNote(const std::string& path, const RawMesh& output) {
  if (MeshFileExtension(path) != ".stl" || HasFaceGroups(output)) return "";
  const double rounding = BinaryStlRounding(output);
  if (rounding == 0.0) return "";
  float lo[3], hi[3];
  for (int i = 0; i < 3; ++i) lo[i] = hi[i] = output.positions.empty() ? 0.0f : output.positions[i];
  for (size_t c = 0; c < output.positions.size(); ++c) {
    lo[c % 3] = std::min(lo[c % 3], output.positions[c]);
    hi[c % 3] = std::max(hi[c % 3], output.positions[c]);
  }
  const double diagonal =
      std::hypot(double(hi[0]) - lo[0], double(hi[1]) - lo[1], double(hi[2]) - lo[2]);
  return absl::StrFormat(
      "binary STL holds absolute float coordinates: far from the origin (the part's centre is "
      "near %g %g %g) its corners moved by up to %g (%.2g%% of the diagonal); write .ply, .obj, "
      ".off or .msh to keep every digit",
      output.origin[0], output.origin[1], output.origin[2], rounding,
      diagonal > 0 ? 100 * rounding / diagonal : 0.0);
}

}  // namespace

int FinishRun(const SimplifyArgs& args, RawMesh& output, const GroupNames& group_names,
              RunReport& report) {
  report.output_vertices = output.num_vertices();
  report.output_faces = output.num_faces();
  const auto t0 = std::chrono::steady_clock::now();
  if (args.drop_face_data) DropUnheldFaceData(MeshFileExtension(args.output), &output);
  if (absl::Status s = WriteMeshFile(args.output, output, group_names); !s.ok()) {
    PrintError("femsimp: cannot write %s: %s\n", args.output.c_str(),
               std::string(s.message()).c_str());
    return kExitOutputFailed;
  }
  report.write_seconds = SecondsSince(t0);
  if (const std::string note = OutputRoundingNote(args.output, output); !note.empty())
    report.output_warnings.push_back(note);
  std::printf("%s", Summary(report).c_str());
  if (!args.stats_json.empty()) {
    if (absl::Status s = WriteTextFile(args.stats_json, ReportJson(report)); !s.ok()) {
      PrintError("femsimp: --stats-json: %s\n", std::string(s.message()).c_str());
      return kExitOutputFailed;
    }
  }
  return kExitOk;
}

RepairOptions RepairOptionsFor(const SimplifyArgs& args) {
  RepairOptions o = args.options.repair;
  o.max_records_per_kind = kReportRepairRecordsPerKind;
  o.threads = args.options.threads;
  return o;
}

void PrintInvalidInput(const SimplifyArgs& args, const absl::Status& status) {
  // One defect per line: the list after the strict mode's counts, its items apart.
  std::string text(status.message());
  if (const size_t at = text.find("): ");
      absl::StartsWith(text, "repair is off") && at != std::string::npos)
    text.replace(at, 3, "):\n  ");
  PrintError("femsimp: %s is not a valid mesh: %s\n", args.input.c_str(),
             absl::StrReplaceAll(text, {{"; ", ";\n  "}}).c_str());
  if (args.options.repair.mode == RepairMode::kOff)
    PrintError(
        "femsimp: repair is off (--repair off); with --repair on (the default) "
        "femsimp repairs what it can and reports every change\n");
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace femsimp::cli
