#pragma once

#include <algorithm>
#include <cmath>
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

// The uncertainty columns of object_motions.csv (",est_sigma_tx,...,est_sigma_rz": the square roots of
// the covariance's diagonal) and of object_speeds.csv (",speed_sigma_mps"): blank when unknown.
constexpr const char* kMotionSigmaColumns = ",est_sigma_tx,est_sigma_ty,est_sigma_tz,est_sigma_rx,est_sigma_ry,est_sigma_rz";
constexpr const char* kSpeedSigmaColumn = ",speed_sigma_mps";

template <typename Covariance>
void PutMotionSigmas(std::ostream& out, const Covariance* covariance) {
  const bool known = covariance && !covariance->isZero(0.0);
  for (int i = 0; i < 6; ++i) {
    out << ',';
    if (known) out << std::sqrt(std::max(0.0, (*covariance)(i, i)));
  }
}

inline void PutSpeedSigma(std::ostream& out, double sigma_mps) {
  out << ',';
  if (sigma_mps > 0.0) out << sigma_mps;
}

}  // namespace dslam
