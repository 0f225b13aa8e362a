#include "server/log.h"

#include <cstdio>
#include <mutex>

#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "common/escape.h"

namespace femsimp::server {

std::string EscapedForLog(std::string_view line) { return EscapeControlCharacters(line); }

void LogLine(std::string_view line) {
  static std::mutex mu;
  const std::string ts = absl::FormatTime("%Y-%m-%dT%H:%M:%E3SZ", absl::Now(), absl::UTCTimeZone());
  const std::string text = EscapedForLog(line);
  std::lock_guard<std::mutex> lock(mu);
  std::fprintf(stderr, "%s %s\n", ts.c_str(), text.c_str());
  std::fflush(stderr);
}

}  // namespace femsimp::server
