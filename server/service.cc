#include "server/service.h"

#include <algorithm>
#include <chrono>
#include <new>
#include <optional>
#include <string>
#include <thread>

#include "absl/strings/str_cat.h"
#include "engine/mesh.h"
#include "engine/prepare.h"
#include "fecheck/tet_mesh.h"
#include "fecheck/tools.h"
#include "proto/fe_check_wire.h"
#include "proto/wire.h"
#include "server/log.h"
#include "server/request_reader.h"
#include "server/result_stream.h"
#include "server/status_util.h"
#include "server/stopwatch.h"

namespace femsimp::server {
namespace {

using Stream = grpc::ServerReaderWriter<v1::SimplifyResponse, v1::SimplifyRequest>;
// How often the handler of a running job looks at its call (cancelled, client gone) besides
// waking for progress and at the call's deadline.
constexpr auto kPoll = std::chrono::milliseconds(50);
// The client cancels its call at its own deadline; the server's copy of it is later by the
// transit time and by the rounding up of the grpc-timeout header. A cancel that arrives this
// close to the server's deadline is the deadline.
constexpr auto kDeadlineSlack = std::chrono::milliseconds(100);

bool DeadlinePassed(const grpc::ServerContext* ctx, std::chrono::milliseconds slack = {}) {
  return ctx->deadline() <= std::chrono::system_clock::now() + slack;
}

// The status of a call the client ended (cancelled, or its deadline passed) at `when`.
grpc::Status ClientEnded(const grpc::ServerContext* ctx, const char* when) {
  if (DeadlinePassed(ctx, kDeadlineSlack))
    return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED,
                        absl::StrCat("deadline exceeded ", when));
  return grpc::Status(grpc::StatusCode::CANCELLED, absl::StrCat("cancelled by the client ", when));
}

// The handler's next wake-up: the next poll, or the call's deadline when that comes first.
Job::Clock::time_point NextWake(const grpc::ServerContext* ctx) {
  const auto poll = Job::Clock::now() + kPoll;
  const auto to_deadline = ctx->deadline() - std::chrono::system_clock::now();
  if (to_deadline >= kPoll || to_deadline <= decltype(to_deadline)::zero()) return poll;
  return Job::Clock::now() + std::chrono::duration_cast<Job::Clock::duration>(to_deadline);
}

// The repair options of a job: its own (mode, weld tolerance). A strict refusal names only the
// first few defects of each kind: its message travels in the status trailer, whose size gRPC
// bounds (8 KiB by default).
RepairOptions ServerRepairOptions(const Job& job) {
  RepairOptions o = job.options().repair;
  if (o.mode == RepairMode::kOff) o.max_records_per_kind = 5;
  o.threads = job.options().threads;
  return o;
}

// A status message kept well under the trailer limit.
std::string Bounded(std::string message) {
  constexpr size_t kMaxMessageBytes = 6000;
  if (message.size() > kMaxMessageBytes) {
    message.resize(kMaxMessageBytes);
    message += " ... (cut; run femsimp locally with --repair-details for the full list)";
  }
  return message;
}

// A stalled upload or result the watchdog ended (the client sees its call cancelled; the job's
// status, the log and the metrics say why).
grpc::Status WatchExpired(const std::string& job_id, const std::string& why) {
  LogLine(
      absl::StrCat(job_id.empty() ? "call" : absl::StrCat("job ", job_id), " cancelled: ", why));
  return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED, why);
}

// What a job may ask of this server beyond the option table's ranges: the cell back end runs a
// host thread and allocates a local store per SPE.
std::optional<std::string> OverServerLimits(const SimplifyOptions& o, const ServerConfig& c) {
  if (o.backend != Backend::kCell) return std::nullopt;
  if (o.cell.spes > c.max_spes)
    return absl::StrCat("spec.options.cell.spes: ", o.cell.spes,
                        " is above this server's limit of ", c.max_spes, " (--max_spes)");
  const int64_t kib = int64_t{o.cell.spes} * o.cell.local_store_kib;
  if (kib > int64_t{c.max_cell_local_store_mib} * 1024)
    return absl::StrCat("spec.options.cell: ", o.cell.spes, " SPEs x ", o.cell.local_store_kib,
                        " KiB of local store = ", kib / 1024,
                        " MiB is above this server's limit of ", c.max_cell_local_store_mib,
                        " MiB (--max_cell_local_store_mib)");
  return std::nullopt;
}

}  // namespace

SimplifierService::SimplifierService(const ServerConfig& config, JobQueue& queue,
                                     JobRegistry& registry, JobRunner& runner, Metrics& metrics,
                                     TokenAuthenticator auth)
    : config_(config),
      queue_(queue),
      registry_(registry),
      runner_(runner),
      metrics_(metrics),
      memory_(config.memory_budget_mib << 20,
              [&metrics](uint64_t admitted) { metrics.SetMemoryAdmitted(admitted); }),
      auth_(std::move(auth)) {
  metrics_.SetMemoryBudget(memory_.budget());
}

void SimplifierService::UpdateQueueGauge() { metrics_.SetQueueDepth(queue_.waiting()); }

grpc::Status SimplifierService::Pushback(grpc::ServerContext* ctx, const std::string& why) const {
  ctx->AddTrailingMetadata("grpc-retry-pushback-ms", std::to_string(config_.retry_pushback_ms));
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      absl::StrCat(why, "; retry after ", config_.retry_pushback_ms, " ms"));
}

grpc::Status SimplifierService::Simplify(grpc::ServerContext* ctx, Stream* stream) {
  ++active_simplify_calls_;
  struct Active {
    std::atomic<int>& n;
    ~Active() { --n; }
  } active{active_simplify_calls_};
  std::string tenant;  // the job counter's label; none for a call that is not authenticated
  grpc::Status status = [&]() -> grpc::Status {
    if (shutting_down_.load())
      return grpc::Status(grpc::StatusCode::UNAVAILABLE, "server is shutting down");
    if (grpc::Status s = auth_.Authenticate(*ctx, &tenant); !s.ok()) return s;
    CallWatchdog::Watch upload(watchdog_, ctx,
                               {.idle_seconds = config_.upload_idle_seconds,
                                .deadline_seconds = config_.upload_deadline_seconds,
                                .what = "upload",
                                .idle_flag = "--upload_idle_seconds",
                                .deadline_flag = "--upload_deadline_seconds"});
    RequestReader reader(
        [stream, &upload](v1::SimplifyRequest* r) {
          const bool got = stream->Read(r);
          upload.Touch();
          return got;
        },
        config_);
    absl::StatusOr<v1::JobSpec> spec = reader.ReadSpec();
    if (!spec.ok()) {
      if (std::string why = upload.expired(); !why.empty()) return WatchExpired("", why);
      if (ctx->IsCancelled()) return ClientEnded(ctx, "before the job spec");
      return ToGrpc(spec.status());
    }
    absl::StatusOr<SimplifyOptions> options =
        wire::FromProto(spec->options(), config_.threads_per_job, config_.threads_per_job);
    if (!options.ok())
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          absl::StrCat("spec.options: ", options.status().message()));
    if (std::optional<std::string> over = OverServerLimits(*options, config_))
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, *over);
    // The FE check's options and tools before the upload: a server without tetgen or ccx says so
    // before the client sends its mesh.
    std::optional<fecheck::FeCheckOptions> fe_check;
    if (spec->fe_check()) {
      absl::StatusOr<fecheck::FeCheckOptions> fe =
          wire::FeCheckOptionsFromProto(spec->fe_check_options());
      if (!fe.ok())
        return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            absl::StrCat("spec.fe_check_options: ", fe.status().message()));
      if (absl::Status tools = fecheck::LocateTools(); !tools.ok())
        return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                            absl::StrCat("fe_check: this server cannot run it: ", tools.message()));
      fe_check = *fe;
    }
    // Memory by the declared size: a job that could never fit is refused for good, one that
    // does not fit beside the admitted jobs is told to come back (as for a full queue).
    const uint64_t need = EstimateJobBytes(spec->vertex_count(), spec->face_count(), *options);
    const auto mib = [](uint64_t bytes) { return (bytes + (1 << 20) - 1) >> 20; };
    if (need > memory_.budget())
      return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                          absl::StrCat("the job needs an estimated ", mib(need), " MiB (",
                                       spec->vertex_count(), " vertices, ", spec->face_count(),
                                       " faces declared), above this server's memory budget of ",
                                       memory_.budget() >> 20, " MiB (--memory_budget_mib)"));
    // Admission before the upload, so a full server does not receive the mesh first.
    if (!queue_.TryReserve())
      return Pushback(ctx, absl::StrCat("job queue is full (queue_capacity = ", queue_.capacity(),
                                        ", ", runner_.running(), " jobs running)"));
    std::optional<MemoryBudget::Lease> memory = memory_.TryAdmit(need);
    if (!memory) {
      queue_.CancelReservation();
      return Pushback(ctx, absl::StrCat("not enough memory now: the job needs an estimated ",
                                        mib(need), " MiB; jobs admitted: ", memory_.leases(),
                                        ", holding ", mib(memory_.admitted()), " of ",
                                        memory_.budget() >> 20, " MiB (--memory_budget_mib)"));
    }
    auto job = std::make_shared<Job>(registry_.NewId(), spec->client_label(), *options,
                                     spec->vertex_count(), spec->face_count(), tenant, fe_check);
    // One tenant may not take every slot: its unfinished jobs are bounded, atomically with
    // their registration.
    if (!registry_.AddWithin(job, static_cast<size_t>(config_.max_jobs_per_tenant))) {
      queue_.CancelReservation();
      return Pushback(ctx, absl::StrCat("tenant '", tenant, "' has ", config_.max_jobs_per_tenant,
                                        " unfinished jobs (--max_jobs_per_tenant)"));
    }
    grpc::Status s;
    try {
      s = RunJob(ctx, stream, job, reader, *spec, upload);
    } catch (const std::bad_alloc&) {  // the job fails, the server goes on
      s = grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                       absl::StrCat("not enough memory for the job (", spec->vertex_count(),
                                    " vertices, ", spec->face_count(),
                                    " faces declared) while receiving or preparing its mesh"));
    }
    job->Close(s);
    registry_.MarkFinished(job);
    return s;
  }();
  metrics_.JobFinished(status.error_code(), tenant);
  return status;
}

grpc::Status SimplifierService::RunJob(grpc::ServerContext* ctx, Stream* stream,
                                       const std::shared_ptr<Job>& job, RequestReader& reader,
                                       const v1::JobSpec& spec, CallWatchdog::Watch& upload) {
  // The queue slot reserved at admission goes back on every way out but the queue, an
  // exception (out of memory) included.
  struct Reservation {
    JobQueue& queue;
    bool held = true;
    ~Reservation() {
      if (held) queue.CancelReservation();
    }
  } reservation{queue_};
  v1::SimplifyResponse resp;
  resp.mutable_accepted()->set_job_id(job->id());
  resp.mutable_accepted()->set_queue_position(static_cast<uint32_t>(queue_.waiting()));
  if (!stream->Write(resp)) {
    return grpc::Status(grpc::StatusCode::CANCELLED, "client went away");
  }

  Stopwatch upload_time;
  absl::StatusOr<RawMesh> raw = reader.ReadMesh(spec);
  upload.Done();
  if (std::string why = upload.expired(); !why.empty()) return WatchExpired(job->id(), why);
  if (job->cancelled()) {
    return job->cancel_status();
  }
  if (ctx->IsCancelled()) {
    return ClientEnded(ctx, "during the upload");
  }
  if (!raw.ok()) {
    return ToGrpc(raw.status());
  }
  const Backend backend = job->options().backend;
  metrics_.StageFinished(Stage::kUpload, backend, upload_time.seconds());
  absl::StatusOr<PreparedMesh> prepared = PrepareMesh(*std::move(raw), ServerRepairOptions(*job));
  *raw = RawMesh();
  if (!prepared.ok()) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        Bounded(absl::StrCat("invalid mesh: ", prepared.status().message())));
  }
  metrics_.StageFinished(Stage::kRepair, backend, prepared->times.repair_seconds);
  metrics_.StageFinished(Stage::kBuild, backend,
                         prepared->times.order_seconds + prepared->times.build_seconds);
  // An FE check needs a closed input: refused before the job queues, not after it ran.
  if (job->fe_check()) {
    absl::StatusOr<RawMesh> repaired =
        OutputMesh(prepared->mesh, prepared->seam_map, prepared->shared_walls);
    absl::Status closed = repaired.ok() ? fecheck::CheckClosedSolid(*repaired) : repaired.status();
    if (!closed.ok())
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          absl::StrCat("fe_check: the input (as repaired): ", closed.message()));
  }
  metrics_.Repaired(prepared->report);
  LogLine(absl::StrCat("job ", job->id(), " ", prepared->report.Summary()));
  RepairReport repair = std::move(prepared->report);
  {
    v1::SimplifyResponse resp;
    wire::RepairToProto(repair, resp.mutable_repair());
    if (!stream->Write(resp)) {
      return ClientEnded(ctx, "after the upload");
    }
  }
  job->Enqueue(*std::move(prepared));
  reservation.held = false;  // PushReserved takes the slot over
  if (!queue_.PushReserved(job))
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "server is shutting down");
  UpdateQueueGauge();
  return Follow(ctx, stream, job, repair);
}

grpc::Status SimplifierService::Follow(grpc::ServerContext* ctx, Stream* stream,
                                       const std::shared_ptr<Job>& job,
                                       const RepairReport& repair) {
  size_t sent_passes = 0;
  int last_position = -2;
  bool client_gone = false, cancel_seen = false;
  for (;;) {
    Job::Update u = job->WaitForChange(sent_passes, cancel_seen, NextWake(ctx));
    sent_passes += u.passes.size();
    cancel_seen = u.cancel_requested;
    if (!u.done && !u.cancel_requested &&
        (client_gone || ctx->IsCancelled() || DeadlinePassed(ctx))) {
      const grpc::Status ended = ClientEnded(ctx, "while the job ran");
      job->RequestCancel(ended.error_code(), ended.error_message());
      u.cancel_requested = cancel_seen = true;
    }
    // A cancelled job still waiting is taken out here; a running one stops within a pass.
    if (!u.done && u.cancel_requested && queue_.Remove(job.get())) {
      UpdateQueueGauge();
      job->FinishCancelled();
      u.done = true;
    }
    // Passes fetched together with the end of the job still go out before the result.
    for (const PassStats& p : u.passes) {
      v1::SimplifyResponse resp;
      wire::ToProto(p, resp.mutable_progress());
      if (!client_gone && !stream->Write(resp)) client_gone = true;
    }
    if (u.done) break;
    if (client_gone) continue;  // wait for the worker to let go of the job
    if (u.state == JobState::kQueued) {
      int pos = queue_.Position(job.get());
      if (pos >= 0 && pos != last_position) {
        v1::SimplifyResponse resp;
        resp.mutable_queue_update()->set_queue_position(static_cast<uint32_t>(pos));
        if (!stream->Write(resp)) client_gone = true;
        last_position = pos;
      }
    }
  }

  Job::Output output;
  if (grpc::Status s = job->TakeOutput(&output); !s.ok()) return s;
  if (client_gone || ctx->IsCancelled()) return ClientEnded(ctx, "before the result");
  v1::SimplifyResponse resp;
  const SimplifyResult& r = output.result;
  v1::Result* m = resp.mutable_result();
  m->set_job_id(job->id());
  m->set_input_vertices(r.input_vertices);
  m->set_input_faces(r.input_faces);
  m->set_output_vertices(output.mesh.num_vertices());
  m->set_output_faces(output.mesh.num_faces());
  wire::OriginToProto(output.mesh.origin, m->mutable_origin());
  m->set_engine_seconds(r.engine_seconds);
  m->set_busy_seconds(r.busy_seconds);
  m->set_queue_seconds(output.queue_seconds);
  m->set_stop_reason(StopReasonName(r.stop_reason));
  if (r.limiting_rule != Reject::kCount) m->set_limiting_rule(RejectName(r.limiting_rule));
  m->set_passes(static_cast<uint32_t>(r.passes.size()));
  m->set_modeled_cycles(r.modeled_cycles);
  m->set_has_face_groups(!output.mesh.face_groups.empty());
  m->set_contexts(job->contexts());
  for (const FaceField& field : output.mesh.face_fields) m->add_face_field_names(field.name);
  wire::FidelityToProto(r, m);
  wire::RepairToProto(repair, m->mutable_repair());
  if (output.fe_check) wire::ToProto(*output.fe_check, m->mutable_fe_check());
  // A client that stops reading would hold the output mesh (a Write waits for it): cancelled.
  CallWatchdog::Watch download(watchdog_, ctx,
                               {.idle_seconds = config_.result_idle_seconds,
                                .what = "result",
                                .idle_flag = "--result_idle_seconds"});
  const auto write = [&](const v1::SimplifyResponse& r) {
    const bool written = stream->Write(r);
    download.Touch();
    return written;
  };
  ChunkStreamTimes times{.encode_seconds = output.output_seconds};
  Stopwatch result_write;
  bool ok = write(resp);
  times.write_seconds += result_write.seconds();
  if (ok) ok = StreamMeshChunks(output.mesh, write, &times);
  download.Done();
  if (std::string why = download.expired(); !why.empty()) return WatchExpired(job->id(), why);
  if (!ok) return grpc::Status(grpc::StatusCode::CANCELLED, "client went away during the result");
  metrics_.StageFinished(Stage::kEncode, job->options().backend, times.encode_seconds);
  metrics_.StageFinished(Stage::kDownload, job->options().backend, times.write_seconds);
  return grpc::Status::OK;
}

namespace {

// Job ids are 32 hex digits (JobRegistry::NewId): anything else names no job, and is not echoed
// back (a megabyte of it, or control characters, would only burden the status and the logs).
grpc::Status CheckJobId(const std::string& id) {
  constexpr size_t kMaxJobIdBytes = 64;
  const bool printable = std::all_of(id.begin(), id.end(), [](char c) {
    return static_cast<unsigned char>(c) >= 0x20 && static_cast<unsigned char>(c) < 0x7f;
  });
  if (id.size() <= kMaxJobIdBytes && printable) return grpc::Status::OK;
  return grpc::Status(
      grpc::StatusCode::INVALID_ARGUMENT,
      absl::StrCat("job_id: ", id.size(), " bytes",
                   printable ? "" : " with control or non-ASCII characters",
                   " (a job id is at most ", kMaxJobIdBytes, " printable ASCII characters)"));
}

}  // namespace

grpc::Status SimplifierService::FindOwnJob(const grpc::ServerContext* ctx, const std::string& id,
                                           std::shared_ptr<Job>* job) const {
  std::string tenant;
  if (grpc::Status s = auth_.Authenticate(*ctx, &tenant); !s.ok()) return s;
  if (grpc::Status s = CheckJobId(id); !s.ok()) return s;
  *job = registry_.Find(id);
  if (*job == nullptr || (*job)->tenant() != tenant)
    return grpc::Status(grpc::StatusCode::NOT_FOUND, absl::StrCat("no job '", id, "'"));
  return grpc::Status::OK;
}

grpc::Status SimplifierService::GetJob(grpc::ServerContext* ctx, const v1::GetJobRequest* req,
                                       v1::JobInfo* resp) {
  std::shared_ptr<Job> job;
  if (grpc::Status s = FindOwnJob(ctx, req->job_id(), &job); !s.ok()) return s;
  job->Describe(resp, queue_.Position(job.get()));
  return grpc::Status::OK;
}

grpc::Status SimplifierService::CancelJob(grpc::ServerContext* ctx, const v1::CancelJobRequest* req,
                                          v1::CancelJobResponse* resp) {
  std::shared_ptr<Job> job;
  if (grpc::Status s = FindOwnJob(ctx, req->job_id(), &job); !s.ok()) return s;
  const JobState found = job->RequestCancel(grpc::StatusCode::CANCELLED, "cancelled by CancelJob");
  resp->set_previous_state(ToProto(found));
  if (!IsEnded(found)) LogLine(absl::StrCat("job ", job->id(), ": CancelJob"));
  return grpc::Status::OK;
}

grpc::Status SimplifierService::ListJobs(grpc::ServerContext* ctx, const v1::ListJobsRequest* req,
                                         v1::ListJobsResponse* resp) {
  std::string tenant;
  if (grpc::Status s = auth_.Authenticate(*ctx, &tenant); !s.ok()) return s;
  for (const auto& job : registry_.List(req->include_finished()))
    if (job->tenant() == tenant) job->Describe(resp->add_jobs(), queue_.Position(job.get()));
  return grpc::Status::OK;
}

grpc::Status SimplifierService::ServerInfo(grpc::ServerContext* ctx, const v1::ServerInfoRequest*,
                                           v1::ServerInfoResponse* resp) {
  std::string tenant;
  if (grpc::Status s = auth_.Authenticate(*ctx, &tenant); !s.ok()) return s;
  resp->set_version(kVersion);
  resp->add_backends("native");
  resp->add_backends("cell");
  resp->set_workers(static_cast<uint32_t>(config_.workers));
  resp->set_queue_capacity(static_cast<uint32_t>(config_.queue_capacity));
  resp->set_threads_per_job(static_cast<uint32_t>(config_.threads_per_job));
  resp->set_max_vertices(config_.max_vertices);
  resp->set_max_faces(config_.max_faces);
  resp->set_max_request_bytes(config_.max_request_bytes);
  resp->set_queued_jobs(static_cast<uint32_t>(queue_.waiting()));
  resp->set_running_jobs(static_cast<uint32_t>(runner_.running()));
  resp->set_host_cores(std::max(1u, std::thread::hardware_concurrency()));
  return grpc::Status::OK;
}

}  // namespace femsimp::server
