// The start and the end shared by the local and the remote simplify run: the report skeleton,
// the input file, the output file, the summary, the clock.
#pragma once

#include <chrono>
#include <optional>

#include "absl/status/status.h"
#include "client/args.h"
#include "client/report.h"
#include "engine/io/face_data.h"
#include "engine/raw_mesh.h"

namespace femsimp::cli {

RunReport StartReport(const SimplifyArgs& args);

// Reads args.input and records its vertex and face counts and face data; on failure prints the
// reason on stderr and returns nullopt (the caller exits with kExitInputUnreadable). OBJ group
// names and MSH physical names go to group_names, for writing OUT; what the reader left out of
// the file to report.input_warnings.
std::optional<RawMesh> ReadInput(const SimplifyArgs& args, RunReport& report,
                                 GroupNames* group_names);

// Before the run: can OUT's format hold the input's face groups and fields, and its group names
// (an OBJ name in an MSH file)? If not, prints why and returns false (the caller exits with
// kExitOutputFailed), unless --drop-face-data, which records what OUT will lack in the report.
bool CheckOutputFormat(const SimplifyArgs& args, const RawMesh& input,
                       const GroupNames& group_names, RunReport& report);

// The end of a run: writes OUT (dropping what its format cannot hold under --drop-face-data),
// records its size and the time the write took, prints the summary and writes --stats-json.
// kExitOk, or kExitOutputFailed after printing why.
int FinishRun(const SimplifyArgs& args, RawMesh& output, const GroupNames& group_names,
              RunReport& report);

// The repair options of a run: the table's (mode, weld tolerance), with the records the report
// keeps per kind (kReportRepairRecordsPerKind: the summary lists the first few, --repair-details
// and --stats-json all of them).
RepairOptions RepairOptionsFor(const SimplifyArgs& args);

// An input that failed PrepareMesh (exit code kExitInputInvalid): the message on stderr, one
// defect per line.
void PrintInvalidInput(const SimplifyArgs& args, const absl::Status& status);

double SecondsSince(std::chrono::steady_clock::time_point t0);

}  // namespace femsimp::cli
