#pragma once
// Rigid transforms (SE(3)) with the group operations the estimator and the metrics need.
// Tangent vectors are ordered [rho (translation part, m); phi (rotation vector, rad)].

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dslam {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;

class SE3 {
 public:
  SE3() : q_(Eigen::Quaterniond::Identity()), t_(Vec3::Zero()) {}
  SE3(const Eigen::Quaterniond& q, const Vec3& t) : q_(q.normalized()), t_(t) {}
  SE3(const Mat3& R, const Vec3& t) : q_(Eigen::Quaterniond(R).normalized()), t_(t) {}

  static SE3 Identity() { return SE3(); }
  // Builds from a 4x4 homogeneous matrix; the rotation block is re-orthonormalised.
  static SE3 FromMatrix(const Mat4& T);
  static SE3 Exp(const Vec6& xi);
  Vec6 Log() const;

  SE3 inverse() const;
  SE3 operator*(const SE3& other) const { return SE3(q_ * other.q_, q_ * other.t_ + t_); }
  Vec3 operator*(const Vec3& p) const { return q_ * p + t_; }

  const Eigen::Quaterniond& rotation() const { return q_; }
  Mat3 rotationMatrix() const { return q_.toRotationMatrix(); }
  const Vec3& translation() const { return t_; }
  Mat4 matrix() const;
  // Rotation angle in radians, in [0, pi].
  double angle() const;

  bool isApprox(const SE3& other, double tol = 1e-9) const;

 private:
  Eigen::Quaterniond q_;
  Vec3 t_;
};

// Geodesic interpolation a * Exp(s * Log(a^-1 b)); s in [0, 1] goes from a to b.
SE3 Interpolate(const SE3& a, const SE3& b, double s);

Mat3 Hat(const Vec3& v);
// Rotation vector (axis * angle) of a rotation, angle in [0, pi].
Vec3 RotationLog(const Eigen::Quaterniond& q);
Eigen::Quaterniond RotationExp(const Vec3& phi);

constexpr double kRadToDeg = 57.29577951308232;
constexpr double kDegToRad = 1.0 / kRadToDeg;

}  // namespace dslam
