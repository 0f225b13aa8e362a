#include "server/config.h"

#include <algorithm>
#include <thread>

#include "absl/strings/str_cat.h"

namespace femsimp::server {

std::string NormalizeConfig(ServerConfig* c) {
  if (c->workers < 1) return absl::StrCat("--workers = ", c->workers, " must be >= 1");
  if (c->queue_capacity < 0)
    return absl::StrCat("--queue_capacity = ", c->queue_capacity, " must be >= 0");
  if (c->max_vertices < 3 || c->max_faces < 1) return "--max_vertices / --max_faces too small";
  if (c->max_request_bytes < (64u << 10))
    return absl::StrCat("--max_request_bytes = ", c->max_request_bytes, " must be >= 65536");
  if (c->grace_period_seconds < 0) return "--grace_period_seconds must be >= 0";
  if (c->max_connection_age_seconds < 0) return "--max_connection_age_seconds must be >= 0";
  int cores = std::max(1u, std::thread::hardware_concurrency());
  if (c->threads_per_job < 0)
    return absl::StrCat("--threads_per_job = ", c->threads_per_job, " must be >= 0");
  // More threads than cores only adds contention to a shared-memory pass.
  if (c->threads_per_job == 0) c->threads_per_job = std::max(1, cores / c->workers);
  c->threads_per_job = std::min(c->threads_per_job, cores);
  return "";
}

}  // namespace femsimp::server
