#include "server/job_runner.h"

#include <new>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "engine/crossings.h"
#include "fecheck/fe_check.h"
#include "proto/wire.h"
#include "server/log.h"
#include "server/status_util.h"
#include "server/stopwatch.h"

namespace femsimp::server {

JobRunner::JobRunner(int workers, JobQueue& queue, JobRegistry& registry, Metrics& metrics)
    : queue_(queue), registry_(registry), metrics_(metrics), pool_(workers) {
  driver_ = std::thread([this] { pool_.Run([this](int) { Work(); }); });
}

JobRunner::~JobRunner() {
  queue_.Close();
  Join();
}

void JobRunner::Join() {
  if (driver_.joinable()) driver_.join();
}

void JobRunner::Work() {
  while (std::shared_ptr<Job> job = queue_.Pop()) {
    metrics_.SetQueueDepth(queue_.waiting());
    Run(job);
  }
}

absl::StatusOr<fecheck::FeCheckReport> JobRunner::RunFeCheck(const Job& job,
                                                             const std::optional<RawMesh>& input,
                                                             const RawMesh& output) {
  if (!input)
    return absl::ResourceExhaustedError(
        absl::StrFormat("FE check: not enough memory to keep the input (%d vertices, %d faces)",
                        job.input_vertices(), job.input_faces()));
  LogLine(absl::StrFormat("job %s fe_check start: %u and %u faces", job.id(), input->num_faces(),
                          output.num_faces()));
  fecheck::FeCheckControl control;
  control.cancelled = [&job] { return job.cancelled(); };
  control.on_stage = [&job](const fecheck::FeStage& s) {
    LogLine(absl::StrFormat("job %s fe_check %d/%d: %s", job.id(), s.step, s.steps, s.text));
  };
  absl::StatusOr<fecheck::FeCheckReport> report;
  try {
    fecheck::FeCheckOptions options = *job.fe_check();
    options.threads = job.contexts();  // CalculiX gets the job's share of the cores
    report = fecheck::RunFeCheck(*input, output, options, control, {"input", "output"});
  } catch (const std::bad_alloc&) {
    report = absl::ResourceExhaustedError("FE check: not enough memory");
  }
  if (!report.ok()) {
    // NotFound (a tool gone since admission) is the server's state, not the job's mistake.
    const absl::StatusCode code = report.status().code() == absl::StatusCode::kNotFound
                                      ? absl::StatusCode::kFailedPrecondition
                                      : report.status().code();
    return absl::Status(code, absl::StrCat("FE check: ", report.status().message()));
  }
  const fecheck::FeDifferences d = fecheck::Compare(report->original, report->simplified);
  LogLine(absl::StrFormat("job %s fe_check end: volume %+.4f%% moments %.4f%% frequencies %.4f%%",
                          job.id(), 100 * d.volume, 100 * d.worst_moment, 100 * d.worst_frequency));
  return report;
}

void JobRunner::Run(const std::shared_ptr<Job>& job) {
  std::optional<PreparedMesh> input = job->Start();
  if (!input) return;  // ended while queued (cancelled, shutdown)
  Mesh* mesh = &input->mesh;
  const double queued = job->queued_seconds();
  if (job->cancelled()) {  // cancelled between Pop and Start
    job->FinishCancelled();
    registry_.MarkFinished(job);
    return;
  }

  metrics_.SetRunning(++running_);
  const SimplifyOptions& o = job->options();
  LogLine(absl::StrFormat(
      "job %s start: label=\"%s\" vertices=%u faces=%u fields=%u backend=%s contexts=%d "
      "ratio=%g target_vertices=%u cost=%s tolerance=%g tolerance_relative=%g queued=%.3fs",
      job->id(), job->label(), job->input_vertices(), job->input_faces(),
      mesh->field_names().size(), wire::BackendName(o.backend), job->contexts(), o.ratio,
      o.target_vertices, CostKindName(o.cost), o.tolerance, o.tolerance_relative, queued));

  SimplifyControl control;
  control.cancelled = [&job] { return job->cancelled(); };
  control.on_removal_start = [&job](int pass) { job->StartRemoval(pass); };
  control.on_pass = [&](const PassStats& p) {
    metrics_.PassFinished(o.backend, p);
    job->AddPass(p);
  };
  // Running out of memory fails this job, not the server, and frees its slot like any failure.
  const auto out_of_memory = [&job](const char* what) {
    return absl::ResourceExhaustedError(
        absl::StrFormat("not enough memory %s (%d vertices, %d faces)", what, job->input_vertices(),
                        job->input_faces()));
  };
  // The FE check compares the input as repaired with the output: a copy before the engine runs.
  std::optional<RawMesh> fe_input;
  if (job->fe_check()) {
    absl::StatusOr<RawMesh> copy;
    try {
      copy = OutputMesh(*mesh, input->seam_map, input->shared_walls);
    } catch (const std::bad_alloc&) {
      copy = out_of_memory("to keep the input for the FE check");
    }
    if (copy.ok()) fe_input = *std::move(copy);
  }
  absl::StatusOr<SimplifyResult> result;
  Stopwatch engine_time;
  try {
    result = Simplify(*mesh, o, control);
  } catch (const std::bad_alloc&) {
    result = out_of_memory("to simplify the mesh");
  }
  if (result.ok()) metrics_.StageFinished(Stage::kEngine, o.backend, engine_time.seconds());

  grpc::Status status;
  if (!result.ok()) {
    status = ToGrpc(absl::Status(result.status().code(), absl::StrCat("simplification failed: ",
                                                                      result.status().message())));
  } else if (job->cancelled()) {
    status = job->cancel_status();
  }
  RawMesh output;
  Stopwatch output_time;
  double output_seconds = 0;
  if (result.ok() && status.ok()) {
    absl::StatusOr<RawMesh> out;
    try {
      out = OutputMesh(*mesh, input->seam_map, input->shared_walls);
    } catch (const std::bad_alloc&) {
      out = out_of_memory("to write the simplified mesh");
    }
    if (out.ok()) result->output_crossings = CheckOutputCrossings(*out, o.threads);
    output_seconds = output_time.seconds();
    if (out.ok()) {
      output = *std::move(out);
    } else {
      status = ToGrpc(out.status());
      result = out.status();
    }
  }
  input.reset();  // the engine's arrays go before the next job starts
  std::optional<fecheck::FeCheckReport> fe_report;
  if (job->fe_check() && result.ok() && status.ok()) {
    absl::StatusOr<fecheck::FeCheckReport> fe = RunFeCheck(*job, fe_input, output);
    if (fe.ok()) {
      fe_report = *std::move(fe);
    } else if (job->cancelled()) {
      status = job->cancel_status();
    } else {
      status = ToGrpc(fe.status());
      result = fe.status();
    }
  }
  // Metrics before the job ends: a client that saw its job end then sees it counted.
  if (result.ok() && status.ok())
    metrics_.JobCompleted(o.backend, job->contexts(), result->engine_seconds, queued, *result);
  metrics_.SetRunning(--running_);
  if (!result.ok())
    job->Finish(JobState::kFailed, status);
  else if (!status.ok())
    job->FinishCancelled();
  else
    job->Succeed(*result, std::move(output), output_seconds, std::move(fe_report));
  registry_.MarkFinished(job);

  const double run_seconds = job->run_seconds();
  if (result.ok() && status.ok()) {
    double speedup = result->engine_seconds > 0 ? result->busy_seconds / result->engine_seconds : 0;
    LogLine(absl::StrFormat(
        "job %s end: OK vertices=%u->%u faces=%u->%u passes=%u engine=%.3fs busy=%.3fs "
        "speedup=%.2f stop=%s run=%.3fs",
        job->id(), result->input_vertices, result->output_vertices, result->input_faces,
        result->output_faces, result->passes.size(), result->engine_seconds, result->busy_seconds,
        speedup, StopReasonName(result->stop_reason), run_seconds));
  } else {
    LogLine(absl::StrFormat("job %s end: %s \"%s\" passes=%u run=%.3fs", job->id(),
                            StatusCodeName(status.error_code()), status.error_message(),
                            result.ok() ? result->passes.size() : 0, run_seconds));
  }
}

}  // namespace femsimp::server
