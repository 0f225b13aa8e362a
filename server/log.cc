#include "server/log.h"

#include <cstdio>
#include <mutex>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "common/escape.h"
#include "google/protobuf/stubs/logging.h"

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

void RouteProtobufLogs() {
  google::protobuf::SetLogHandler(
      [](google::protobuf::LogLevel level, const char* file, int line, const std::string& message) {
        static constexpr const char* kLevels[] = {"INFO", "WARNING", "ERROR", "FATAL"};
        const int i = static_cast<int>(level);
        LogLine(absl::StrCat("libprotobuf ", i >= 0 && i < 4 ? kLevels[i] : "?", " ", file, ":",
                             line, ": ", message));
      });
}

}  // namespace femsimp::server
