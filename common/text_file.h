// A small file read whole (certificates, keys, token lists), with the error naming the flag or
// variable that named it.
#pragma once

#include <string>

#include "absl/status/statusor.h"

namespace femsimp {

// NOT_FOUND "WHAT: cannot read PATH" when the file cannot be opened or read.
absl::StatusOr<std::string> ReadTextFile(const std::string& what, const std::string& path);

}  // namespace femsimp
