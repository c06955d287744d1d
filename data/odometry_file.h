#pragma once
// odometry.txt: a vehicle's odometry increments, one line per frame after the first:
//   frame tx ty tz qx qy qz qw sigma_tx sigma_ty sigma_tz sigma_rx sigma_ry sigma_rz
// (T_prev_curr = T_world_camera[frame-1]^-1 * T_world_camera[frame], quaternion Hamilton x y z w,
// sigmas in metres and radians). Lines starting with '#' are comments.

#include <map>
#include <string>

#include "data/measurements.h"

namespace dslam {

// Throws std::runtime_error "path:line: what" for a short line, a non-number, a non-finite value, a
// quaternion far from unit norm, a non-positive sigma or frames not strictly increasing.
std::map<int, OdometryMeasurement> ReadOdometryFile(const std::string& path);
void WriteOdometryFile(const std::string& path, const std::map<int, OdometryMeasurement>& odometry);

}  // namespace dslam
