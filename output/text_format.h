#pragma once

#include <algorithm>
#include <charconv>
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

// `value` as a stream at precision `digits` writes it in its default notation (printf's %.*g), through
// std::to_chars: the same characters without the stream's locale machinery. A run's map points are most of
// its text (formatting them took 1.3 % of the demo run's CPU).
inline void PutGeneral(std::ostream& out, double value, int digits) {
  char buffer[40];  // a sign, 17 digits, a point and a 4-digit exponent at most
  if (digits < 1 || digits > 17) {  // more digits than a double holds: the stream's own way, its precision kept
    const std::streamsize kept = out.precision(digits);
    out << value;
    out.precision(kept);
    return;
  }
  const std::to_chars_result end = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, digits);
  out.write(buffer, end.ptr - buffer);
}

// The headers of object_motions.csv and object_speeds.csv, for every writer. The uncertainty columns
// (est_sigma_*: the square roots of the motion covariance's diagonal; speed_sigma_mps) are blank when
// unknown.
constexpr const char* kObjectMotionsHeader =
    "frame,object_id,is_dynamic,est_tx,est_ty,est_tz,est_qx,est_qy,est_qz,est_qw,"
    "gt_tx,gt_ty,gt_tz,gt_qx,gt_qy,gt_qz,gt_qw,est_sigma_tx,est_sigma_ty,est_sigma_tz,est_sigma_rx,est_sigma_ry,est_sigma_rz";
// object_speeds.csv also says where the object is: the centroid of its measured points in the frame's
// camera (centroid_x_m ... ; x right, y down, z forward) and its box in the image (box_x, box_y: top-left
// corner, pixels), blank when unknown.
constexpr const char* kObjectSpeedsHeader =
    "frame,object_id,is_dynamic,est_speed_mps,gt_speed_mps,speed_sigma_mps,centroid_x_m,centroid_y_m,centroid_z_m,"
    "box_x,box_y,box_w,box_h";

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
