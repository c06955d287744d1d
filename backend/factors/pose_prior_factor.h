#pragma once

#include <ceres/autodiff_cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam {

// Prior: r = diag(1/sigma) * Log(T_prior^-1 * T). Variable: one pose block (T_world_camera[0]).
class PosePriorFactor {
 public:
  PosePriorFactor(const SE3& T_prior, const Vec6& sigma)
      : prior_inv_(T_prior.inverse()), inv_sigma_(sigma.cwiseInverse()) {}

  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const Eigen::Map<const Quat<T>> q(pose);
    const Eigen::Map<const V3<T>> t(pose + 4);
    const Quat<T> q_p = prior_inv_.rotation().cast<T>();
    const Quat<T> q_err = q_p * q;
    const V3<T> t_err = q_p * t + prior_inv_.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = SE3LogT<T>(q_err, t_err).cwiseProduct(inv_sigma_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const SE3& T_prior, const Vec6& sigma) {
    return new ceres::AutoDiffCostFunction<PosePriorFactor, 6, kPoseBlockSize>(new PosePriorFactor(T_prior, sigma));
  }

 private:
  SE3 prior_inv_;
  Vec6 inv_sigma_;
};

}  // namespace dslam
