#pragma once
// Residuals and analytic Jacobians of the two hot factors (point measurement, point motion): their one
// definition, used by the fixed-lag smoother's own solver, by the marginalisation and, through the cost
// functions of point_measurement_factor.h and point_motion_factor.h, by Ceres' batch solver. Pose blocks
// are perturbed on the right in rotation and additively in translation: (q, t) <- (q * Exp(phi), t + dt),
// tangent [dt; phi], matching SE3's [rho; phi] order. Each is checked against Ceres autodiff of reference
// functors (tests/support/reference_point_factors.h, tests/backend/factors/analytic_jacobians_test.cpp).

#include <Eigen/Core>

#include "geometry/se3.h"

namespace dslam {

using Mat36 = Eigen::Matrix<double, 3, 6>;

// r = W (R^T (l - t) - z), W = diag(inv_sigma). J_pose = [-W R^T, W [p_c]x], J_point = W R^T.
inline Vec3 PointMeasurementResidual(const Mat3& R, const Vec3& t, const Vec3& l, const Vec3& z, const Vec3& inv_sigma,
                                     Mat36* J_pose, Mat3* J_point) {
  const Vec3 p_camera = R.transpose() * (l - t);
  if (J_pose || J_point) {
    const Mat3 WRt = inv_sigma.asDiagonal() * R.transpose();
    if (J_pose) {
      J_pose->leftCols<3>() = -WRt;
      J_pose->rightCols<3>() = inv_sigma.asDiagonal() * Hat(p_camera);
    }
    if (J_point) *J_point = WRt;
  }
  return inv_sigma.cwiseProduct(p_camera - z);
}

// r = S ((l_curr - c) - R (l_prev - c) - t'), (R, t') the motion about anchor c (MotionVariable).
// J_prev = -S R, J_curr = S, J_H = [-S, S R [l_prev - c]x].
inline Vec3 PointMotionResidual(const Mat3& R, const Vec3& t_anchor, const Vec3& anchor, const Vec3& l_prev,
                                const Vec3& l_curr, const Mat3& S, Mat3* J_prev, Mat3* J_curr, Mat36* J_motion) {
  const Vec3 a = l_prev - anchor;
  const Mat3 SR = S * R;
  if (J_prev) *J_prev = -SR;
  if (J_curr) *J_curr = S;
  if (J_motion) {
    J_motion->leftCols<3>() = -S;
    J_motion->rightCols<3>() = SR * Hat(a);
  }
  return S * ((l_curr - anchor) - R * a - t_anchor);
}

}  // namespace dslam
