// An interval of allowed values with open, closed or absent ends, and its words in messages
// and help ("in [0, 60)", ">= 1", "> 0"). Shared by the engine's option table and every
// executable's flags.
#pragma once

#include <limits>
#include <string>

namespace femsimp {

struct Range {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo = -kInf, hi = kInf;
  bool lo_closed = true, hi_closed = true;  // an infinite end is never reached either way

  static constexpr Range Closed(double lo, double hi) { return {lo, hi, true, true}; }
  static constexpr Range ClosedOpen(double lo, double hi) { return {lo, hi, true, false}; }
  static constexpr Range OpenClosed(double lo, double hi) { return {lo, hi, false, true}; }
  static constexpr Range AtLeast(double lo) { return {lo, kInf, true, false}; }
  static constexpr Range Above(double lo) { return {lo, kInf, false, false}; }
  static constexpr Range Any() { return {}; }

  // False for NaN and for infinities outside a closed finite end.
  bool Contains(double v) const {
    return (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi) && v == v &&
           v != kInf && v != -kInf;
  }
  bool bounded() const { return lo != -kInf || hi != kInf; }
  // "in [0, 60)", "in (0, 180]", ">= 1", "> 0", "<= 5"; "any number" when unbounded.
  std::string Text() const;
};

// A number as ranges and defaults print it: integers without exponent, others with up to 10
// significant digits (4000000000, 0.01, 1e-06).
std::string FormatNumber(double v);

}  // namespace femsimp
