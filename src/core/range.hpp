#pragma once
// A valid interval for one input, declared once and used by every layer that checks it (the deck's
// key table, the sand model, the docs), so that the layers cannot disagree.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"

namespace ejecta {

struct Range {
  double lo = -INFINITY, hi = INFINITY;
  bool lo_open = false, hi_open = false;

  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi); }
  // "[0, 1]", "(0, 1000]"
  std::string text() const { return fmt::format("{}{:g}, {:g}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]"); }
};

// Throws InputError naming `field` when v is not finite or not inside r.
inline void requireInRange(const std::string& field, double v, const Range& r, const std::string& unit) {
  if (!std::isfinite(v)) throw InputError(field, "must be a finite number");
  if (!r.contains(v)) throw InputError(field, fmt::format("{:g} {} is out of range; valid {} {}", v, unit, r.text(), unit));
}

}  // namespace ejecta
