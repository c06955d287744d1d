#pragma once

#include "backend/factors/relative_pose_residual.h"

namespace dslam {

// Odometry: r = diag(1/sigma) * Log(o_k^-1 * T_world_camera[k-1]^-1 * T_world_camera[k]).
// Variables: T_world_camera[k-1], T_world_camera[k]. sigma = [translation m x3; rotation rad x3].
struct OdometryFactor {
  static ceres::CostFunction* Create(const SE3& T_prev_curr_measured, const Vec6& sigma) {
    return RelativePoseResidual::Create(T_prev_curr_measured, sigma);
  }
};

}  // namespace dslam
