#pragma once
// Layout of SE(3) parameter blocks shared by every factor and the manifold:
// [qx, qy, qz, qw, tx, ty, tz] (Eigen quaternion storage order, then translation).
// Templated so that Ceres' autodiff Jets flow through; every factor's residual builds on these. Free of
// Ceres' headers, as most of the code that includes it never builds a problem (the manifold: pose_manifold.h).

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/se3.h"

namespace dslam {

constexpr int kPoseBlockSize = 7;
using PoseBlock = std::array<double, kPoseBlockSize>;

inline void PoseToBlock(const SE3& T, double* block) {
  const auto& q = T.rotation();
  block[0] = q.x();
  block[1] = q.y();
  block[2] = q.z();
  block[3] = q.w();
  block[4] = T.translation().x();
  block[5] = T.translation().y();
  block[6] = T.translation().z();
}

inline SE3 BlockToPose(const double* block) {
  return SE3(Eigen::Quaterniond(block[3], block[0], block[1], block[2]), Vec3(block[4], block[5], block[6]));
}

inline Eigen::Matrix3d BlockRotationMatrix(const double* block) {
  return Eigen::Map<const Eigen::Quaterniond>(block).toRotationMatrix();
}
inline Vec3 BlockTranslation(const double* block) { return Vec3(block[4], block[5], block[6]); }

// The tangent [dt; phi] from block x0 to block x, the inverse of (q, t) <- (q0 * Exp(phi), t0 + dt).
inline Eigen::Matrix<double, 6, 1> PoseBlockMinus(const double* x, const double* x0) {
  const Eigen::Map<const Eigen::Quaterniond> q(x), q0(x0);
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = BlockTranslation(x) - BlockTranslation(x0);
  d.tail<3>() = RotationLog(q0.conjugate() * q);
  return d;
}

// The block moved by a tangent step: (q * Exp(phi), t + dt), delta = [dt; phi] (the pose manifold's Plus).
inline void PoseBlockPlus(const double* block, const Eigen::Matrix<double, 6, 1>& delta, double* out) {
  const Eigen::Map<const Eigen::Quaterniond> q(block);
  Eigen::Map<Eigen::Quaterniond> q_out(out);
  q_out = (q * RotationExp(delta.tail<3>())).normalized();
  for (int i = 0; i < 3; ++i) out[4 + i] = block[4 + i] + delta[i];
}

// d(block)/d(tangent) at the block: the 7x6 Jacobian of PoseBlockPlus at a zero step (what Ceres' pose
// manifold multiplies a cost function's Jacobian by).
inline Eigen::Matrix<double, 7, 6> PoseBlockPlusJacobian(const double* block) {
  const double x = block[0], y = block[1], z = block[2], w = block[3];
  Eigen::Matrix<double, 7, 6> J = Eigen::Matrix<double, 7, 6>::Zero();
  // d(q * [phi/2, 1])/d(phi) in (x, y, z, w) storage.
  J.block<4, 3>(0, 3) << 0.5 * w, -0.5 * z, 0.5 * y,  //
      0.5 * z, 0.5 * w, -0.5 * x,                      //
      -0.5 * y, 0.5 * x, 0.5 * w,                      //
      -0.5 * x, -0.5 * y, -0.5 * z;
  J.block<3, 3>(4, 0).setIdentity();
  return J;
}

// An analytic Jacobian in the tangent [dt; phi] handed to Ceres as a Jacobian in the block's seven
// coordinates, J_ambient, with J_ambient * PoseBlockPlusJacobian = J_tangent exactly: the quaternion
// columns are 2 J_phi Q^T (Q = 2 d(q)/d(phi) has orthonormal columns for a unit quaternion), the
// translation columns J_dt. Its component along q itself is zero, a direction the manifold never moves in.
template <int Rows>
Eigen::Matrix<double, Rows, 7, Rows == 1 ? Eigen::ColMajor : Eigen::RowMajor> AmbientJacobian(
    const Eigen::Matrix<double, Rows, 6>& J_tangent, const double* block) {
  const Eigen::Matrix<double, 4, 3> Q_half = PoseBlockPlusJacobian(block).block<4, 3>(0, 3);
  Eigen::Matrix<double, Rows, 7, Rows == 1 ? Eigen::ColMajor : Eigen::RowMajor> J;
  J.template leftCols<4>() = 4.0 * J_tangent.template rightCols<3>() * Q_half.transpose();
  J.template rightCols<3>() = J_tangent.template leftCols<3>();
  return J;
}

template <typename T>
using Quat = Eigen::Quaternion<T>;
template <typename T>
using V3 = Eigen::Matrix<T, 3, 1>;

// Relative transform a^-1 * b of two pose blocks.
template <typename T>
void RelativePose(const T* a, const T* b, Quat<T>* q_ab, V3<T>* t_ab) {
  const Eigen::Map<const Quat<T>> q_a(a), q_b(b);
  const Eigen::Map<const V3<T>> t_a(a + 4), t_b(b + 4);
  const Quat<T> q_a_inv = q_a.conjugate();
  *q_ab = q_a_inv * q_b;
  *t_ab = q_a_inv * (t_b - t_a);
}

// SE(3) logarithm [rho; phi] of (q, t), written so autodiff stays finite at the identity.
template <typename T>
Eigen::Matrix<T, 6, 1> SE3LogT(const Quat<T>& q_in, const V3<T>& t) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  Quat<T> q = q_in;
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  const T s_sq = q.vec().squaredNorm();
  V3<T> phi;
  if (s_sq < T(1e-12)) {
    phi = T(2) * q.vec() / q.w();
  } else {
    const T s = sqrt(s_sq);
    phi = (T(2) * atan2(s, q.w()) / s) * q.vec();
  }
  const T theta_sq = phi.squaredNorm();
  T coeff;
  if (theta_sq < T(1e-10)) {
    coeff = T(1.0 / 12.0) + theta_sq / T(720.0);
  } else {
    const T theta = sqrt(theta_sq);
    coeff = (T(1) - theta * sin(theta) / (T(2) * (T(1) - cos(theta)))) / theta_sq;
  }
  const V3<T> phi_x_t = phi.cross(t);
  Eigen::Matrix<T, 6, 1> xi;
  xi.template head<3>() = t - T(0.5) * phi_x_t + coeff * phi.cross(phi_x_t);
  xi.template tail<3>() = phi;
  return xi;
}

}  // namespace dslam
