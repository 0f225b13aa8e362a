// Shared by the shape rules: the angle helper.
#pragma once

#include <cmath>
#include <numbers>

namespace femsimp {

inline double CosDeg(double degrees) { return std::cos(degrees * std::numbers::pi / 180.0); }

}  // namespace femsimp
