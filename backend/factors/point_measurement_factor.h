#pragma once

#include <ceres/sized_cost_function.h>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/pose_block.h"

namespace dslam {

// 3D point measurement: residual = diag(1/sigma) * (T_world_camera^-1 * l_world - z_camera).
// Variables: T_world_camera[k] (pose block), l_world[i][k] (3 doubles). Residual and Jacobians are
// PointMeasurementResidual's (analytic_jacobians.h), the one definition the fixed-lag solver uses too.
class PointMeasurementFactor final : public ceres::SizedCostFunction<3, kPoseBlockSize, 3> {
 public:
  PointMeasurementFactor(const Vec3& z_camera, const Vec3& sigma_m)
      : z_camera_(z_camera), inv_sigma_(sigma_m.cwiseInverse()) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* camera = parameters[0];
    const Vec3 l(parameters[1][0], parameters[1][1], parameters[1][2]);
    const bool want_pose = jacobians && jacobians[0], want_point = jacobians && jacobians[1];
    Mat36 J_pose;
    Mat3 J_point;
    Eigen::Map<Vec3> r(residuals);
    r = PointMeasurementResidual(BlockRotationMatrix(camera), BlockTranslation(camera), l, z_camera_, inv_sigma_,
                                 want_pose ? &J_pose : nullptr, want_point ? &J_point : nullptr);
    if (want_pose) {
      Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[0]);
      J = AmbientJacobian<3>(J_pose, camera);
    }
    if (want_point) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[1]);
      J = J_point;
    }
    return true;
  }

  static ceres::CostFunction* Create(const Vec3& z_camera, const Vec3& sigma_m) {
    return new PointMeasurementFactor(z_camera, sigma_m);
  }

 private:
  Vec3 z_camera_;
  Vec3 inv_sigma_;
};

}  // namespace dslam
