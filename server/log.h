// One-line server log on stderr with a UTC timestamp (the service has no logging library).
#pragma once

#include <string>
#include <string_view>

namespace femsimp::server {

// Control characters (newlines included) and DEL in `line` are written as \xNN: text a client
// chose (its label, a file name in a message) can neither forge a log line nor reach a
// terminal as an escape sequence.
void LogLine(std::string_view line);

// What LogLine writes for `line` (after its timestamp).
std::string EscapedForLog(std::string_view line);

}  // namespace femsimp::server
