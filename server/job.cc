#include "server/job.h"

namespace femsimp::server {

Job::Job(std::string id_, std::string label_, SimplifyOptions options_, uint64_t vertices,
         uint64_t faces, bool face_groups)
    : id(std::move(id_)),
      label(std::move(label_)),
      options(options_),
      input_vertices(vertices),
      input_faces(faces),
      has_face_groups(face_groups) {}

void Job::RequestCancel(grpc::StatusCode code, const std::string& message) {
  {
    std::lock_guard<std::mutex> lock(mu);
    if (cancel_code != grpc::StatusCode::OK) return;
    cancel_code = code;
    cancel_message = message;
  }
  cancel_.store(true);
  cv.notify_all();
}

void Job::Finish(JobState final_state, grpc::Status s) {
  {
    std::lock_guard<std::mutex> lock(mu);
    state = final_state;
    status = std::move(s);
    finished_at = Clock::now();
    mesh.reset();  // free the input as soon as the job is over
  }
  cv.notify_all();
}

bool Job::done() const {
  return state == JobState::kSucceeded || state == JobState::kFailed ||
         state == JobState::kCancelled;
}

int Job::contexts() const {
  return options.backend == Backend::kCell ? options.cell.spes : options.threads;
}

void Job::Describe(v1::JobInfo* info, int queue_position) {
  std::lock_guard<std::mutex> lock(mu);
  auto secs = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  const Clock::time_point now = Clock::now();
  info->set_job_id(id);
  info->set_client_label(label);
  info->set_state(ToProto(state));
  info->set_queue_position(queue_position < 0 ? 0 : queue_position);
  info->set_passes_done(static_cast<uint32_t>(passes.size()));
  info->set_input_vertices(input_vertices);
  info->set_input_faces(input_faces);
  info->set_vertices_left(passes.empty() ? input_vertices : passes.back().vertices_left);
  info->set_backend(options.backend == Backend::kCell ? v1::BACKEND_CELL : v1::BACKEND_NATIVE);
  if (queued_at != Clock::time_point{}) {
    Clock::time_point end = started_at != Clock::time_point{} ? started_at
                            : done()                          ? finished_at
                                                              : now;
    info->set_queued_seconds(secs(queued_at, end));
  }
  if (started_at != Clock::time_point{})
    info->set_running_seconds(secs(started_at, done() ? finished_at : now));
  if (done()) {
    info->set_status_code(StatusCodeName(status.error_code()));
    info->set_status_message(status.error_message());
  }
}

const char* StateName(JobState s) {
  switch (s) {
    case JobState::kUploading:
      return "uploading";
    case JobState::kQueued:
      return "queued";
    case JobState::kRunning:
      return "running";
    case JobState::kSucceeded:
      return "succeeded";
    case JobState::kFailed:
      return "failed";
    case JobState::kCancelled:
      return "cancelled";
  }
  return "unknown";
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
