// The two pieces of JSON text every hand-written JSON document of femsimp needs (--stats-json,
// femsimp check --json): a string with its escapes and a number (JSON has no NaN or infinity).
#pragma once

#include <string>

namespace femsimp {

std::string JsonString(const std::string& s);
std::string JsonNumber(double d);  // %.9g; null when not finite

}  // namespace femsimp
