#include "client/remote_run.h"
#include "common/escape.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "client/channel_security.h"
#include "client/exit_codes.h"
#include "client/remote_call.h"
#include "client/report.h"
#include "client/retry.h"
#include "client/run_input.h"
#include "engine/io/mesh_io.h"
#include "proto/fe_check_wire.h"
#include "proto/wire.h"

namespace femsimp::cli {
namespace {

std::atomic<bool> g_interrupted{false};
void OnSigint(int) { g_interrupted.store(true); }

}  // namespace

int RunRemote(const SimplifyArgs& args) {
  RunReport report = StartReport(args);
  auto t0 = std::chrono::steady_clock::now();
  GroupNames group_names;  // the server knows group ids only; names stay here for OUT
  std::optional<RawMesh> raw = ReadInput(args, report, &group_names);
  if (!raw) return kExitInputUnreadable;
  if (!CheckOutputFormat(args, *raw, group_names, report)) return kExitOutputFailed;
  report.load_seconds = SecondsSince(t0);

  v1::JobSpec spec;
  wire::ToProto(args.options, args.threads_given, spec.mutable_options());
  spec.set_client_label(args.label.empty() ? args.input : args.label);
  if (args.fe_check) {  // run by the server after the simplification
    spec.set_fe_check(true);
    wire::ToProto(args.fe_check_options, spec.mutable_fe_check_options());
  }

  absl::StatusOr<ChannelSecurity> security = ResolveSecurity(args.security);
  if (!security.ok()) {
    PrintError("femsimp: %s\n", std::string(security.status().message()).c_str());
    return kExitUsage;
  }
  RetryOptions retry;
  retry.channel = MakeChannel(args.server, *security);
  auto stub = v1::Simplifier::NewStub(retry.channel);
  retry.policy.max_attempts = args.max_attempts;
  if (args.deadline_seconds > 0)
    retry.deadline = std::chrono::system_clock::now() +
                     std::chrono::microseconds(static_cast<int64_t>(args.deadline_seconds * 1e6));

  // Ctrl-C cancels the job (the running attempt or the wait for the next); the server stops it
  // within a pass.
  JobCanceller job_canceller;
  retry.canceller = &job_canceller;
  std::signal(SIGINT, OnSigint);
  std::atomic<bool> call_done{false};
  std::thread canceller([&] {
    while (!call_done.load()) {
      if (g_interrupted.load()) {
        job_canceller.Cancel();
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });

  const bool tty = isatty(fileno(stdout));
  bool bar_drawn = false;
  RemoteCallbacks cb;
  cb.on_accepted = [&](const v1::Accepted& a) {
    report.job_id = a.job_id();
    if (!args.quiet)
      std::printf("job %s accepted by %s (%u ahead in the queue)\n", a.job_id().c_str(),
                  args.server.c_str(), a.queue_position());
    if (!args.quiet && !tty) std::printf("%s\n", PassTableHeader(args.options.backend).c_str());
    std::fflush(stdout);
  };
  cb.on_repair = [&](const v1::RepairReport& r) {
    if (args.quiet) return;
    std::printf("repaired by the server: %s\n", wire::RepairFromProto(r).Summary().c_str());
    std::fflush(stdout);
  };
  cb.on_queue_update = [&](const v1::QueueUpdate& q) {
    if (args.quiet) return;
    if (tty) {
      std::printf("\rqueued: %u jobs ahead\x1b[K", q.queue_position());
      bar_drawn = true;
    } else {
      std::printf("queued: %u jobs ahead\n", q.queue_position());
    }
    std::fflush(stdout);
  };
  cb.on_progress = [&](const v1::Progress& m) {
    PassStats p = wire::FromProto(m);
    if (!args.quiet) {
      if (tty) {
        std::printf("%s", ProgressLine(p, report.input_vertices, args.options).c_str());
        bar_drawn = true;
      } else {
        std::printf("%s\n", PassTableRow(p, args.options.backend).c_str());
      }
      std::fflush(stdout);
    }
    report.passes.push_back(std::move(p));
  };
  // A failed attempt's passes are not this job's: the next attempt starts from the input again.
  retry.on_retry = [&](int attempt, const RemoteOutcome& failed, std::chrono::milliseconds wait) {
    if (bar_drawn) std::printf("\n");
    bar_drawn = false;
    std::fflush(stdout);
    PrintError("femsimp: attempt %d of %d failed (%s: %s); retrying in %.1f s\n", attempt,
               args.max_attempts, GrpcCodeName(failed.status.error_code()),
               failed.status.error_message().c_str(), static_cast<double>(wait.count()) / 1e3);
    report.passes.clear();
  };
  retry.callbacks = cb;
  RetryCounters counters;
  auto t_rpc = std::chrono::steady_clock::now();
  RemoteOutcome out = SimplifyWithRetry(*stub, spec, *raw, retry, &counters);
  report.attempts = counters.attempts;
  report.transfer_seconds = SecondsSince(t_rpc);
  call_done.store(true);
  canceller.join();
  std::signal(SIGINT, SIG_DFL);
  if (bar_drawn) std::printf("\n");
  *raw = RawMesh();

  if (!out.status.ok()) {
    grpc::StatusCode code = out.status.error_code();
    PrintError("femsimp: %s: %s (%s: %s)\n", args.server.c_str(), GrpcCodeHint(code),
               GrpcCodeName(code), out.status.error_message().c_str());
    if (out.retry_pushback_ms && *out.retry_pushback_ms >= 0)
      PrintError("femsimp: the server suggests retrying after %d ms\n", *out.retry_pushback_ms);
    return kExitGrpcBase + static_cast<int>(code);
  }
  const v1::Result& r = out.result;
  report.engine_seconds = r.engine_seconds();
  report.busy_seconds = r.busy_seconds();
  report.queue_seconds = r.queue_seconds();
  report.stop_reason = r.stop_reason();
  report.limiting_rule = r.limiting_rule();
  report.modeled_cycles = r.modeled_cycles();
  SimplifyResult figures;
  wire::FidelityFromProto(r, &figures);
  report.fidelity = FidelityFigures::Of(figures);
  report.repair = wire::RepairFromProto(r.repair());
  if (r.has_fe_check()) report.fe_check = wire::FromProto(r.fe_check());
  if (args.options.backend == Backend::kNative && r.contexts() > 0)
    report.options.threads = r.contexts();  // what the server actually ran with

  return FinishRun(args, out.output, group_names, report);
}

}  // namespace femsimp::cli
