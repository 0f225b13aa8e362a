#include "server/job.h"

#include <algorithm>

namespace femsimp::server {
namespace {

double Seconds(Job::Clock::time_point a, Job::Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

Job::Job(std::string id, std::string label, SimplifyOptions options, uint64_t vertices,
         uint64_t faces, std::string tenant, std::optional<fecheck::FeCheckOptions> fe_check)
    : id_(std::move(id)),
      label_(std::move(label)),
      tenant_(std::move(tenant)),
      options_(options),
      input_vertices_(vertices),
      input_faces_(faces),
      fe_check_(std::move(fe_check)) {}

int Job::contexts() const {
  return options_.backend == Backend::kCell ? options_.cell.spes : options_.threads;
}

bool Job::done() const { return IsEnded(state_); }

void Job::Enqueue(PreparedMesh input) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (done()) return;
    input_.emplace(std::move(input));
    state_ = JobState::kQueued;
    queued_at_ = Clock::now();
  }
  cv_.notify_all();
}

Job::Update Job::WaitForChange(size_t seen, bool cancel_seen, Clock::time_point until) const {
  std::unique_lock<std::mutex> lock(mu_);
  cv_.wait_until(lock, until,
                 [&] { return passes_.size() > seen || done() || (cancelled() && !cancel_seen); });
  Update u;
  if (passes_.size() > seen)
    u.passes.assign(passes_.begin() + static_cast<std::ptrdiff_t>(seen), passes_.end());
  u.state = state_;
  u.done = done();
  u.cancel_requested = cancelled();
  return u;
}

grpc::Status Job::TakeOutput(Output* out) {
  std::lock_guard<std::mutex> lock(mu_);
  if (!done())
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "job " + id_ + " has not ended yet: no output to take");
  if (!status_.ok()) return status_;
  if (!result_)
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "job " + id_ + ": its output was taken already");
  out->result = std::move(*result_);
  result_.reset();
  out->mesh = std::move(output_);
  output_ = RawMesh();
  out->fe_check = std::move(fe_check_report_);
  fe_check_report_.reset();
  out->queue_seconds = Seconds(queued_at_, started_at_);
  out->output_seconds = output_seconds_;
  return grpc::Status::OK;
}

void Job::Close(const grpc::Status& status) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    const grpc::StatusCode code = status.error_code();
    // A job that succeeded but whose result did not reach the client (not read in time, the
    // client gone): its record says so with the call's status, the one the metrics count.
    if (state_ == JobState::kSucceeded && status_.ok() && code != grpc::StatusCode::OK)
      status_ = grpc::Status(code, "result not delivered: " + status.error_message());
    if (code == grpc::StatusCode::OK)  // the handler returns OK only for an ended job
      FinishLocked(JobState::kFailed, grpc::Status(grpc::StatusCode::INTERNAL,
                                                   "the call ended OK before job " + id_ + " did"));
    else
      FinishLocked(
          code == grpc::StatusCode::CANCELLED || code == grpc::StatusCode::DEADLINE_EXCEEDED
              ? JobState::kCancelled
              : JobState::kFailed,
          status);
    result_.reset();
    output_ = RawMesh();
    fe_check_report_.reset();
  }
  cv_.notify_all();
}

std::optional<PreparedMesh> Job::Start() {
  std::optional<PreparedMesh> input;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (done()) return std::nullopt;
    input = std::move(input_);
    input_.reset();
    state_ = JobState::kRunning;
    started_at_ = Clock::now();
  }
  cv_.notify_all();
  return input;
}

void Job::StartRemoval(int pass) {
  std::lock_guard<std::mutex> lock(mu_);
  passes_started_ = static_cast<uint32_t>(pass);
}

void Job::AddPass(const PassStats& pass) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    passes_.push_back(pass);
  }
  cv_.notify_all();
}

void Job::Succeed(const SimplifyResult& result, RawMesh output, double output_seconds,
                  std::optional<fecheck::FeCheckReport> fe_check) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (!FinishLocked(JobState::kSucceeded, grpc::Status::OK)) return;
    result_ = result;
    output_ = std::move(output);
    output_seconds_ = output_seconds;
    fe_check_report_ = std::move(fe_check);
  }
  cv_.notify_all();
}

bool Job::Finish(JobState final_state, grpc::Status status) {
  bool ended;
  {
    std::lock_guard<std::mutex> lock(mu_);
    ended = FinishLocked(final_state, std::move(status));
  }
  cv_.notify_all();
  return ended;
}

bool Job::FinishCancelled() {
  bool ended;
  {
    std::lock_guard<std::mutex> lock(mu_);
    ended = FinishLocked(JobState::kCancelled, grpc::Status(cancel_code_, cancel_message_));
  }
  cv_.notify_all();
  return ended;
}

bool Job::FinishLocked(JobState final_state, grpc::Status status) {
  if (done()) return false;
  state_ = final_state;
  status_ = std::move(status);
  finished_at_ = Clock::now();
  input_.reset();  // free the input as soon as the job is over
  return true;
}

double Job::QueuedSecondsLocked(Clock::time_point now) const {
  if (queued_at_ == Clock::time_point{}) return 0;
  return Seconds(queued_at_, started_at_ != Clock::time_point{} ? started_at_
                             : done()                           ? finished_at_
                                                                : now);
}

double Job::RunSecondsLocked(Clock::time_point now) const {
  if (started_at_ == Clock::time_point{}) return 0;
  return Seconds(started_at_, done() ? finished_at_ : now);
}

double Job::queued_seconds() const {
  std::lock_guard<std::mutex> lock(mu_);
  return QueuedSecondsLocked(Clock::now());
}

double Job::run_seconds() const {
  std::lock_guard<std::mutex> lock(mu_);
  return RunSecondsLocked(Clock::now());
}

JobState Job::RequestCancel(grpc::StatusCode code, std::string message) {
  JobState found;
  {
    std::lock_guard<std::mutex> lock(mu_);
    found = state_;
    if (done() || cancel_code_ != grpc::StatusCode::OK) return found;
    cancel_code_ = code;
    cancel_message_ = std::move(message);
    cancel_.store(true, std::memory_order_relaxed);
  }
  cv_.notify_all();
  return found;
}

grpc::Status Job::cancel_status() const {
  std::lock_guard<std::mutex> lock(mu_);
  return grpc::Status(cancel_code_, cancel_message_);
}

void Job::Describe(v1::JobInfo* info, int queue_position) const {
  const Clock::time_point now = Clock::now();
  std::lock_guard<std::mutex> lock(mu_);
  info->set_job_id(id_);
  info->set_client_label(label_);
  info->set_state(ToProto(state_));
  info->set_queue_position(queue_position < 0 ? 0 : queue_position);
  info->set_passes_done(static_cast<uint32_t>(passes_.size()));
  info->set_passes_started(std::max(passes_started_, static_cast<uint32_t>(passes_.size())));
  info->set_input_vertices(input_vertices_);
  info->set_input_faces(input_faces_);
  info->set_vertices_left(passes_.empty() ? input_vertices_ : passes_.back().vertices_left);
  info->set_backend(options_.backend == Backend::kCell ? v1::BACKEND_CELL : v1::BACKEND_NATIVE);
  if (queued_at_ != Clock::time_point{}) info->set_queued_seconds(QueuedSecondsLocked(now));
  if (started_at_ != Clock::time_point{}) info->set_running_seconds(RunSecondsLocked(now));
  if (done()) {
    info->set_status_code(StatusCodeName(status_.error_code()));
    info->set_status_message(status_.error_message());
  }
}

v1::JobState ToProto(JobState s) {
  switch (s) {
    case JobState::kUploading:
    case JobState::kQueued:
      return v1::JOB_STATE_QUEUED;
    case JobState::kRunning:
      return v1::JOB_STATE_RUNNING;
    case JobState::kSucceeded:
      return v1::JOB_STATE_SUCCEEDED;
    case JobState::kFailed:
      return v1::JOB_STATE_FAILED;
    case JobState::kCancelled:
      return v1::JOB_STATE_CANCELLED;
  }
  return v1::JOB_STATE_UNSPECIFIED;
}

const char* StatusCodeName(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK:
      return "OK";
    case grpc::StatusCode::CANCELLED:
      return "CANCELLED";
    case grpc::StatusCode::UNKNOWN:
      return "UNKNOWN";
    case grpc::StatusCode::INVALID_ARGUMENT:
      return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND:
      return "NOT_FOUND";
    case grpc::StatusCode::ALREADY_EXISTS:
      return "ALREADY_EXISTS";
    case grpc::StatusCode::PERMISSION_DENIED:
      return "PERMISSION_DENIED";
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::FAILED_PRECONDITION:
      return "FAILED_PRECONDITION";
    case grpc::StatusCode::ABORTED:
      return "ABORTED";
    case grpc::StatusCode::OUT_OF_RANGE:
      return "OUT_OF_RANGE";
    case grpc::StatusCode::UNIMPLEMENTED:
      return "UNIMPLEMENTED";
    case grpc::StatusCode::INTERNAL:
      return "INTERNAL";
    case grpc::StatusCode::UNAVAILABLE:
      return "UNAVAILABLE";
    case grpc::StatusCode::DATA_LOSS:
      return "DATA_LOSS";
    case grpc::StatusCode::UNAUTHENTICATED:
      return "UNAUTHENTICATED";
    default:
      return "UNKNOWN";
  }
}

}  // namespace femsimp::server
