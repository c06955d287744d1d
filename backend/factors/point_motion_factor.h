#pragma once

#include <ceres/sized_cost_function.h>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/pose_block.h"

namespace dslam {

// The ternary point-motion factor that ties a point on a rigid object across frames:
// r = (l_world[i][k] - R_H * l_world[i][k-1] - t_H) / sigma, with (R_H, t_H) = H_world[j][k].
// H is stored about an anchor c (see MotionVariable): with (R, t') the block, H_world = (R, t' + c - R c),
// so r = ((l_k - c) - R (l_{k-1} - c) - t') / sigma — the same residual, better conditioned.
// Variables: l[i][k-1] (3), l[i][k] (3), H_anchor[j][k] (pose block). Residual and Jacobians are
// PointMotionResidual's (analytic_jacobians.h), the one definition the fixed-lag solver uses too.
class PointMotionFactor final : public ceres::SizedCostFunction<3, 3, 3, kPoseBlockSize> {
 public:
  PointMotionFactor(double sigma_m, const Vec3& anchor_world)
      : whitening_(Mat3::Identity() / sigma_m), anchor_(anchor_world) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Vec3 l_prev(parameters[0][0], parameters[0][1], parameters[0][2]);
    const Vec3 l_curr(parameters[1][0], parameters[1][1], parameters[1][2]);
    const double* H = parameters[2];
    const bool want = jacobians != nullptr;
    Mat3 J_prev, J_curr;
    Mat36 J_motion;
    Eigen::Map<Vec3> r(residuals);
    r = PointMotionResidual(BlockRotationMatrix(H), BlockTranslation(H), anchor_, l_prev, l_curr, whitening_,
                            want ? &J_prev : nullptr, want ? &J_curr : nullptr, want ? &J_motion : nullptr);
    if (!want) return true;
    using RowMat3 = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
    if (jacobians[0]) RowMat3{jacobians[0]} = J_prev;
    if (jacobians[1]) RowMat3{jacobians[1]} = J_curr;
    if (jacobians[2]) {
      Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[2]);
      J = AmbientJacobian<3>(J_motion, H);
    }
    return true;
  }

  static ceres::CostFunction* Create(double sigma_m, const Vec3& anchor_world = Vec3::Zero()) {
    return new PointMotionFactor(sigma_m, anchor_world);
  }

 private:
  Mat3 whitening_;
  Vec3 anchor_;
};

}  // namespace dslam
