#pragma once

#include "backend/factors/relative_pose_residual.h"

namespace dslam {

// Motion smoothness: r = diag(1/sigma) * Log(H_world[j][k-1]^-1 * H_world[j][k]).
// Variables: the two consecutive world-frame pose changes of one object.
struct MotionSmoothnessFactor {
  static ceres::CostFunction* Create(const Vec6& sigma) {
    return RelativePoseResidual::Create(SE3::Identity(), sigma);
  }
};

}  // namespace dslam
