#pragma once

#include <ceres/autodiff_cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam {

// Shared residual of the odometry and smoothness factors:
// r = diag(1/sigma) * Log(M^-1 * A^-1 * B) for a measured relative transform M between blocks A and B.
class RelativePoseResidual {
 public:
  RelativePoseResidual(const SE3& measured_a_b, const Vec6& sigma)
      : measured_inv_(measured_a_b.inverse()), inv_sigma_(sigma.cwiseInverse()) {}

  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    Quat<T> q_ab;
    V3<T> t_ab;
    RelativePose(a, b, &q_ab, &t_ab);
    const Quat<T> q_m = measured_inv_.rotation().cast<T>();
    const V3<T> t_m = measured_inv_.translation().cast<T>();
    const Quat<T> q_err = q_m * q_ab;
    const V3<T> t_err = q_m * t_ab + t_m;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = SE3LogT<T>(q_err, t_err).cwiseProduct(inv_sigma_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const SE3& measured_a_b, const Vec6& sigma) {
    return new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, kPoseBlockSize, kPoseBlockSize>(
        new RelativePoseResidual(measured_a_b, sigma));
  }

 private:
  SE3 measured_inv_;
  Vec6 inv_sigma_;
};

}  // namespace dslam
