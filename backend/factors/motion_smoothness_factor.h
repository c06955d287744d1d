#pragma once

#include <ceres/autodiff_cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam {

// Motion smoothness: r = diag(1/sigma) * Log(H[j][k-1]^-1 * H[j][k]), both pose changes expressed about
// the anchor of H[j][k] (the previous one is re-expressed from its own anchor: a shift by the distance
// between the two anchors, about one frame's displacement). Expressed about a point near the object,
// the translation part measures how the object's own motion changed, whatever its distance from the
// world origin. Variables: the two consecutive anchored pose changes of one object.
class MotionSmoothnessFactor {
 public:
  MotionSmoothnessFactor(const Vec6& sigma, const Vec3& anchor_prev, const Vec3& anchor_curr)
      : inv_sigma_(sigma.cwiseInverse()), shift_(anchor_prev - anchor_curr) {}

  template <typename T>
  bool operator()(const T* H_prev, const T* H_curr, T* residual) const {
    const Eigen::Map<const Quat<T>> q1(H_prev), q2(H_curr);
    const Eigen::Map<const V3<T>> t1_own(H_prev + 4), t2(H_curr + 4);
    // H_prev about the current anchor: conjugation by the translation between the anchors.
    const V3<T> d = shift_.cast<T>();
    const V3<T> t1 = t1_own + d - q1 * d;
    const Quat<T> q1_inv = q1.conjugate();
    const Quat<T> q_err = q1_inv * q2;
    const V3<T> t_err = q1_inv * (t2 - t1);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = SE3LogT<T>(q_err, t_err).cwiseProduct(inv_sigma_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const Vec6& sigma, const Vec3& anchor_prev = Vec3::Zero(),
                                     const Vec3& anchor_curr = Vec3::Zero()) {
    return new ceres::AutoDiffCostFunction<MotionSmoothnessFactor, 6, kPoseBlockSize, kPoseBlockSize>(
        new MotionSmoothnessFactor(sigma, anchor_prev, anchor_curr));
  }

 private:
  Vec6 inv_sigma_;
  Vec3 shift_;  // anchor_prev - anchor_curr
};

}  // namespace dslam
