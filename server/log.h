// One-line server log on stderr with a UTC timestamp (the service has no logging library).
#pragma once

#include <string_view>

namespace femsimp::server {

void LogLine(std::string_view line);

}  // namespace femsimp::server
