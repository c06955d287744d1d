#pragma once

#include <ceres/autodiff_cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam {

// The ternary point-motion factor that ties a point on a rigid object across frames:
// r = (l_world[i][k] - R_H * l_world[i][k-1] - t_H) / sigma, with (R_H, t_H) = H_world[j][k].
// H is stored about an anchor c (see MotionVariable): with (R, t') the block, H_world = (R, t' + c - R c),
// so r = ((l_k - c) - R (l_{k-1} - c) - t') / sigma — the same residual, better conditioned.
// Variables: l[i][k-1] (3), l[i][k] (3), H_anchor[j][k] (pose block).
class PointMotionFactor {
 public:
  PointMotionFactor(double sigma_m, const Vec3& anchor_world) : inv_sigma_(1.0 / sigma_m), anchor_(anchor_world) {}

  template <typename T>
  bool operator()(const T* l_prev, const T* l_curr, const T* H_anchor, T* residual) const {
    const V3<T> c = anchor_.cast<T>();
    const V3<T> a = Eigen::Map<const V3<T>>(l_prev) - c, b = Eigen::Map<const V3<T>>(l_curr) - c;
    const Eigen::Map<const Quat<T>> q(H_anchor);
    const Eigen::Map<const V3<T>> t(H_anchor + 4);
    Eigen::Map<V3<T>> r(residual);
    r = (b - (q * a) - t) * T(inv_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(double sigma_m, const Vec3& anchor_world = Vec3::Zero()) {
    return new ceres::AutoDiffCostFunction<PointMotionFactor, 3, 3, 3, kPoseBlockSize>(
        new PointMotionFactor(sigma_m, anchor_world));
  }

 private:
  double inv_sigma_;
  Vec3 anchor_;
};

}  // namespace dslam
