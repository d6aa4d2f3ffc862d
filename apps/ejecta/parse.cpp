#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "commands.hpp"
#include "core/error.hpp"

namespace ejecta::cli {

double parseNumber(const std::string& field, const std::string& text, bool percent_ok) {
  std::string body = text;
  const bool percent = !body.empty() && body.back() == '%';
  if (percent) {
    if (!percent_ok) throw InputError(field, fmt::format("'{}' is not a number (no % here)", text));
    body.pop_back();
  }
  char* end = nullptr;
  const double v = std::strtod(body.c_str(), &end);
  if (body.empty() || end != body.c_str() + body.size() || !std::isfinite(v))
    throw InputError(field, fmt::format("'{}' is not a finite number", text));
  if (percent) return v / 100.0;
  if (percent_ok && v > 1.0)
    throw InputError(field, fmt::format("'{}' is ambiguous: give a fraction in [0, 1] (0.07) or a percentage (7%)", text));
  return v;
}

}  // namespace ejecta::cli
