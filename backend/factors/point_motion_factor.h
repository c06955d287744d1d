#pragma once

#include "backend/factors/pose_block.h"

namespace dslam {

// The ternary point-motion factor that ties a point on a rigid object across frames:
// r = (l_world[i][k] - R_H * l_world[i][k-1] - t_H) / sigma, with (R_H, t_H) = H_world[j][k].
// Variables: l[i][k-1] (3), l[i][k] (3), H_world[j][k] (pose block).
class PointMotionFactor {
 public:
  explicit PointMotionFactor(double sigma_m) : inv_sigma_(1.0 / sigma_m) {}

  template <typename T>
  bool operator()(const T* l_prev, const T* l_curr, const T* H_world, T* residual) const {
    const Eigen::Map<const V3<T>> a(l_prev), b(l_curr);
    const Eigen::Map<const Quat<T>> q(H_world);
    const Eigen::Map<const V3<T>> t(H_world + 4);
    Eigen::Map<V3<T>> r(residual);
    r = (b - (q * a) - t) * T(inv_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(double sigma_m) {
    return new ceres::AutoDiffCostFunction<PointMotionFactor, 3, 3, 3, kPoseBlockSize>(new PointMotionFactor(sigma_m));
  }

 private:
  double inv_sigma_;
};

}  // namespace dslam
