#pragma once

#include <ceres/autodiff_cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam {

// 3D point measurement: residual = diag(1/sigma) * (T_world_camera^-1 * l_world - z_camera).
// Variables: T_world_camera[k] (pose block), l_world[i][k] (3 doubles).
class PointMeasurementFactor {
 public:
  PointMeasurementFactor(const Vec3& z_camera, const Vec3& sigma_m)
      : z_camera_(z_camera), inv_sigma_(sigma_m.cwiseInverse()) {}

  template <typename T>
  bool operator()(const T* T_world_camera, const T* l_world, T* residual) const {
    const Eigen::Map<const Quat<T>> q(T_world_camera);
    const Eigen::Map<const V3<T>> t(T_world_camera + 4);
    const Eigen::Map<const V3<T>> l(l_world);
    const V3<T> p_camera = q.conjugate() * (l - t);
    Eigen::Map<V3<T>> r(residual);
    r = (p_camera - z_camera_.cast<T>()).cwiseProduct(inv_sigma_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const Vec3& z_camera, const Vec3& sigma_m) {
    return new ceres::AutoDiffCostFunction<PointMeasurementFactor, 3, kPoseBlockSize, 3>(
        new PointMeasurementFactor(z_camera, sigma_m));
  }

 private:
  Vec3 z_camera_;
  Vec3 inv_sigma_;
};

}  // namespace dslam
