// Text that came from outside (a client's label, a file name, a file's content quoted in an
// error) is shown with its control characters escaped, so that it can neither forge a log line
// nor reach a terminal as an escape sequence.
#pragma once

#include <string>
#include <string_view>

namespace femsimp {

// Bytes below 0x20 and DEL as \xNN, except those listed in `keep` (e.g. "\n"); everything else
// (UTF-8 included) as it is.
std::string EscapeControlCharacters(std::string_view text, std::string_view keep = {});

// printf to stderr, the formatted text escaped as above (newlines and tabs kept).
void PrintError(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace femsimp
