#include "geometry/se3.h"

#include <cmath>

namespace dslam {
namespace {
// Below this squared angle the closed forms lose precision; their Taylor series are used instead.
constexpr double kSmallAngleSq = 1e-10;

// Left Jacobian V(phi) of SO(3): t = V(phi) * rho in Exp.
Mat3 LeftJacobian(const Vec3& phi) {
  const double theta_sq = phi.squaredNorm();
  const Mat3 Phi = Hat(phi);
  if (theta_sq < kSmallAngleSq) return Mat3::Identity() + 0.5 * Phi + Phi * Phi / 6.0;
  const double theta = std::sqrt(theta_sq);
  return Mat3::Identity() + (1.0 - std::cos(theta)) / theta_sq * Phi +
         (theta - std::sin(theta)) / (theta_sq * theta) * Phi * Phi;
}

Mat3 LeftJacobianInverse(const Vec3& phi) {
  const double theta_sq = phi.squaredNorm();
  const Mat3 Phi = Hat(phi);
  double coeff;
  if (theta_sq < kSmallAngleSq) {
    coeff = 1.0 / 12.0 + theta_sq / 720.0;
  } else {
    const double theta = std::sqrt(theta_sq);
    coeff = (1.0 - theta * std::sin(theta) / (2.0 * (1.0 - std::cos(theta)))) / theta_sq;
  }
  return Mat3::Identity() - 0.5 * Phi + coeff * Phi * Phi;
}
}  // namespace

Mat3 Hat(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Vec3 RotationLog(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // shortest rotation, angle <= pi
  const double s_sq = q.vec().squaredNorm();
  if (s_sq < kSmallAngleSq) return 2.0 * q.vec() / q.w();
  const double s = std::sqrt(s_sq);
  const double theta = 2.0 * std::atan2(s, q.w());
  return theta / s * q.vec();
}

Eigen::Quaterniond RotationExp(const Vec3& phi) {
  const double theta = phi.norm();
  if (theta * theta < kSmallAngleSq) {
    Eigen::Quaterniond q(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z());
    return q.normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, phi / theta));
}

SE3 SE3::FromMatrix(const Mat4& T) {
  Eigen::JacobiSVD<Mat3> svd(T.topLeftCorner<3, 3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0.0) {
    Mat3 U = svd.matrixU();
    U.col(2) *= -1.0;
    R = U * svd.matrixV().transpose();
  }
  return SE3(R, T.topRightCorner<3, 1>());
}

SE3 SE3::Exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  return SE3(RotationExp(phi), LeftJacobian(phi) * rho);
}

Vec6 SE3::Log() const {
  Vec6 xi;
  const Vec3 phi = RotationLog(q_);
  xi.head<3>() = LeftJacobianInverse(phi) * t_;
  xi.tail<3>() = phi;
  return xi;
}

SE3 SE3::inverse() const {
  const Eigen::Quaterniond q_inv = q_.conjugate();
  return SE3(q_inv, -(q_inv * t_));
}

Mat4 SE3::matrix() const {
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = rotationMatrix();
  T.topRightCorner<3, 1>() = t_;
  return T;
}

double SE3::angle() const { return RotationLog(q_).norm(); }

bool SE3::isApprox(const SE3& other, double tol) const {
  return (t_ - other.t_).norm() <= tol && (inverse() * other).angle() <= tol;
}

SE3 Interpolate(const SE3& a, const SE3& b, double s) {
  return a * SE3::Exp(s * (a.inverse() * b).Log());
}

}  // namespace dslam
