#include "common/range.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace femsimp {

std::string FormatNumber(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
    return absl::StrFormat("%.0f", v);
  return absl::StrFormat("%.10g", v);
}

std::string Range::Text() const {
  const bool has_lo = lo != -kInf, has_hi = hi != kInf;
  if (has_lo && has_hi)
    return absl::StrCat("in ", lo_closed ? "[" : "(", FormatNumber(lo), ", ", FormatNumber(hi),
                        hi_closed ? "]" : ")");
  if (has_lo) return absl::StrCat(lo_closed ? ">= " : "> ", FormatNumber(lo));
  if (has_hi) return absl::StrCat(hi_closed ? "<= " : "< ", FormatNumber(hi));
  return "any finite number";
}

}  // namespace femsimp
