#pragma once
// Reference definitions of the two point factors, written as templated functors so that Ceres'
// autodiff differentiates them: the tests hold the analytic residuals and Jacobians the solvers use
// (backend/factors/analytic_jacobians.h, and the cost functions built on them) to these.

#include <ceres/autodiff_cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam::test {

// r = diag(1/sigma) * (T_world_camera^-1 * l_world - z_camera).
class ReferencePointMeasurement {
 public:
  ReferencePointMeasurement(const Vec3& z_camera, const Vec3& sigma_m)
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
    return new ceres::AutoDiffCostFunction<ReferencePointMeasurement, 3, kPoseBlockSize, 3>(
        new ReferencePointMeasurement(z_camera, sigma_m));
  }

 private:
  Vec3 z_camera_;
  Vec3 inv_sigma_;
};

// r = ((l_k - c) - R (l_{k-1} - c) - t') / sigma, (R, t') the motion block about anchor c.
class ReferencePointMotion {
 public:
  ReferencePointMotion(double sigma_m, const Vec3& anchor_world) : inv_sigma_(1.0 / sigma_m), anchor_(anchor_world) {}

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

  static ceres::CostFunction* Create(double sigma_m, const Vec3& anchor_world) {
    return new ceres::AutoDiffCostFunction<ReferencePointMotion, 3, 3, 3, kPoseBlockSize>(
        new ReferencePointMotion(sigma_m, anchor_world));
  }

 private:
  double inv_sigma_;
  Vec3 anchor_;
};

}  // namespace dslam::test
