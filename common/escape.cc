#include "common/escape.h"

#include <cstdarg>
#include <cstdio>
#include <vector>

#include "absl/strings/str_format.h"

namespace femsimp {

std::string EscapeControlCharacters(std::string_view text, std::string_view keep) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 || u == 0x7f) && keep.find(c) == std::string_view::npos)
      absl::StrAppendFormat(&out, "\\x%02x", u);
    else
      out += c;
  }
  return out;
}

void PrintError(const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n < 0) {
    va_end(again);
    return;
  }
  std::vector<char> text(static_cast<size_t>(n) + 1);
  std::vsnprintf(text.data(), text.size(), format, again);
  va_end(again);
  const std::string shown =
      EscapeControlCharacters(std::string_view(text.data(), static_cast<size_t>(n)), "\n\t");
  std::fwrite(shown.data(), 1, shown.size(), stderr);
  std::fflush(stderr);
}

}  // namespace femsimp
