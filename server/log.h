// One-line server log on stderr with a UTC timestamp (the service has no logging library).
#pragma once

#include <string>
#include <string_view>

namespace femsimp::server {

// Control characters (newlines included) and DEL in `line` are written as \xNN: text a client
// chose (its label, a file name in a message) can neither forge a log line nor reach a
// terminal as an escape sequence.
void LogLine(std::string_view line);

// Routes libprotobuf's own log messages (e.g. "String field ... contains invalid UTF-8", which any
// client can provoke with an undecodable request) through LogLine, so that every line of the
// log has a timestamp and escaped text. Call once, before serving.
void RouteProtobufLogs();

// What LogLine writes for `line` (after its timestamp).
std::string EscapedForLog(std::string_view line);

}  // namespace femsimp::server
