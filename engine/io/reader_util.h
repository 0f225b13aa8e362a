// What femsimp's mesh file readers (mesh_readers.cc, msh_reader.cc) share: the error they return
// and how they read numbers from text and from binary data.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <system_error>

#include "absl/status/status.h"
#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"

namespace femsimp::io_internal {

// A reader's refusal: InvalidArgument with the message made of `parts`.
absl::Status Bad(auto&&... parts) { return absl::InvalidArgumentError(absl::StrCat(parts...)); }

// A piece of the file quoted in a message: at most 40 bytes, with control and non-ASCII bytes
// escaped (\x00), so that a binary file read as text names what it found in one short line.
inline std::string Excerpt(absl::string_view s) {
  constexpr size_t kMost = 40;
  const std::string shown = absl::CHexEscape(s.substr(0, kMost));
  return s.size() <= kMost ? shown : absl::StrCat(shown, "...");
}

// A coordinate, as a C++ stream reads a double: correctly rounded; beyond the double range it
// reads as an infinity, for the caller to report, below it as a denormal or zero. Accepts a
// leading '+', and "nan" and "inf" so that they can be reported as such. Coordinates stay in
// double until the part is placed at its local origin (engine/local_origin.h).
inline bool ParseCoordinate(absl::string_view s, double* out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  if (p != s.data() + s.size()) return false;
  if (ec == std::errc::result_out_of_range) *out = std::strtod(std::string(s).c_str(), nullptr);
  return ec == std::errc() || ec == std::errc::result_out_of_range;
}

inline bool ParseDouble(absl::string_view s, double* out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  return ec == std::errc() && p == s.data() + s.size();
}

inline bool ParseInt(absl::string_view s, int64_t* out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  return ec == std::errc() && p == s.data() + s.size();
}

// Coordinates are stored as float: a double that overflows float is as bad as "inf".
inline bool FiniteAsFloat(double d) { return std::isfinite(static_cast<float>(d)); }

// A binary value at p, its bytes reversed when the file's byte order is not the host's.
template <typename T>
T LoadBytes(const char* p, bool swap) {
  std::array<char, sizeof(T)> b;
  std::memcpy(b.data(), p, sizeof(T));
  if (swap) std::reverse(b.begin(), b.end());
  return std::bit_cast<T>(b);
}

}  // namespace femsimp::io_internal
