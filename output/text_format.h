#pragma once

#include <iomanip>
#include <optional>
#include <sstream>
#include <string>

namespace dslam {

// Fixed-point text of an optional number; `missing` when absent (tables: "-", CSV: "").
inline std::string FormatFixed(const std::optional<double>& value, int precision, const std::string& missing) {
  if (!value) return missing;
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << *value;
  return s.str();
}

}  // namespace dslam
