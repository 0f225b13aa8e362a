#include "client/local_run.h"
#include "common/escape.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>

#include "client/exit_codes.h"
#include "client/fe_report.h"
#include "client/report.h"
#include "client/run_input.h"
#include "engine/crossings.h"
#include "engine/io/mesh_io.h"
#include "engine/mesh.h"
#include "engine/prepare.h"

namespace femsimp::cli {
namespace {

std::atomic<bool> g_interrupted{false};
void OnSigint(int) { g_interrupted.store(true); }

}  // namespace

int RunLocal(const SimplifyArgs& args) {
  RunReport report = StartReport(args);
  auto t0 = std::chrono::steady_clock::now();
  GroupNames group_names;
  std::optional<RawMesh> raw = ReadInput(args, report, &group_names);
  if (!raw) return kExitInputUnreadable;
  if (!CheckOutputFormat(args, *raw, group_names, report)) return kExitOutputFailed;
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(*std::move(raw), RepairOptionsFor(args));
  *raw = RawMesh();  // the engine's arrays are the only copy from here on
  if (!prepared.ok()) {
    PrintInvalidInput(args, prepared.status());
    return kExitInputInvalid;
  }
  Mesh* mesh = &prepared->mesh;
  report.repair = std::move(prepared->report);
  // The FE check compares the repaired input with the output: a copy before the engine runs.
  std::optional<RawMesh> fe_input;
  if (args.fe_check) {
    absl::StatusOr<RawMesh> copy = OutputMesh(*mesh, prepared->seam_map, prepared->shared_walls);
    if (!copy.ok()) {
      PrintError("femsimp: %s\n", copy.status().ToString().c_str());
      return kExitEngineFailed;
    }
    fe_input = *std::move(copy);
  }
  report.load_seconds = SecondsSince(t0);

  // Ctrl-C stops the engine within a pass; the partly simplified mesh is still written.
  std::signal(SIGINT, OnSigint);
  SimplifyControl control;
  control.cancelled = [] { return g_interrupted.load(std::memory_order_relaxed); };
  if (!args.quiet) {
    std::printf("%s\n", PassTableHeader(args.options.backend).c_str());
    std::fflush(stdout);
  }
  control.on_pass = [&](const PassStats& p) {
    if (args.quiet) return;
    std::printf("%s\n", PassTableRow(p, args.options.backend).c_str());
    std::fflush(stdout);
  };
  absl::StatusOr<SimplifyResult> result = Simplify(*mesh, args.options, control);
  std::signal(SIGINT, SIG_DFL);
  if (!result.ok()) {
    PrintError("femsimp: simplification failed: %s\n", result.status().ToString().c_str());
    return kExitEngineFailed;
  }
  report.engine_seconds = result->engine_seconds;
  report.busy_seconds = result->busy_seconds;
  report.stop_reason = StopReasonName(result->stop_reason);
  if (result->limiting_rule != Reject::kCount)
    report.limiting_rule = RejectName(result->limiting_rule);
  report.modeled_cycles = result->modeled_cycles;
  report.passes = std::move(result->passes);
  report.fidelity = FidelityFigures::Of(*result);

  absl::StatusOr<RawMesh> out = OutputMesh(*mesh, prepared->seam_map, prepared->shared_walls);
  if (!out.ok()) {
    PrintError("femsimp: %s\n", out.status().ToString().c_str());
    return kExitEngineFailed;
  }
  const auto crossings_start = std::chrono::steady_clock::now();
  report.fidelity.output_crossings = CheckOutputCrossings(*out, args.options.threads);
  report.crossings_seconds = SecondsSince(crossings_start);
  // The check runs before OUT is written, so that the summary and --stats-json hold it; OUT is
  // written whether it succeeds or not.
  int fe_code = kExitOk;
  if (fe_input && !g_interrupted.load()) {
    std::signal(SIGINT, OnSigint);
    absl::StatusOr<fecheck::FeCheckReport> fe = fecheck::RunFeCheck(
        *fe_input, *out, args.fe_check_options, TerminalFeControl(args.quiet, &g_interrupted));
    std::signal(SIGINT, SIG_DFL);
    if (fe.ok()) {
      report.fe_check = *std::move(fe);
    } else {
      PrintError("femsimp: FE check failed: %s\n", std::string(fe.status().message()).c_str());
      fe_code = FeCheckExitCode(fe.status());
    }
  }
  if (int code = FinishRun(args, *out, group_names, report); code != kExitOk) return code;
  if (fe_code != kExitOk) return fe_code;
  return g_interrupted.load() ? kExitCancelled : kExitOk;
}

}  // namespace femsimp::cli
