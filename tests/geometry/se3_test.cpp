#include "geometry/se3.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

Vec6 Twist(double a, double b, double c, double d, double e, double f) { return (Vec6() << a, b, c, d, e, f).finished(); }

TEST(SE3, IdentityIsNeutral) {
  const SE3 T = SE3::Exp(Twist(1, 2, 3, 0.1, 0.2, 0.3));
  EXPECT_TRUE((T * SE3::Identity()).isApprox(T));
  EXPECT_TRUE((SE3::Identity() * T).isApprox(T));
}

TEST(SE3, InverseComposesToIdentity) {
  const SE3 T = SE3::Exp(Twist(1, -2, 3, 0.5, -0.2, 0.9));
  EXPECT_TRUE((T * T.inverse()).isApprox(SE3::Identity()));
  EXPECT_TRUE((T.inverse() * T).isApprox(SE3::Identity()));
}

TEST(SE3, CompositionIsAssociative) {
  const SE3 A = SE3::Exp(Twist(1, 0, 0, 0, 0.3, 0)), B = SE3::Exp(Twist(0, 2, 0, 0.4, 0, 0)),
            C = SE3::Exp(Twist(0, 0, 3, 0, 0, 0.5));
  EXPECT_TRUE(((A * B) * C).isApprox(A * (B * C)));
}

TEST(SE3, ActionMatchesMatrix) {
  const SE3 T = SE3::Exp(Twist(1, 2, 3, 0.3, -0.1, 0.2));
  const Vec3 p(0.5, -1.0, 4.0);
  const Eigen::Vector4d ph = T.matrix() * p.homogeneous();
  EXPECT_NEAR((T * p - ph.head<3>()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(((T.inverse() * T) * p - p).norm(), 0.0, 1e-12);
}

TEST(SE3, ExpLogRoundTrip) {
  for (const Vec6& xi : {Twist(1, 2, 3, 0.1, 0.2, 0.3), Twist(-4, 0.5, 2, 1.0, -2.0, 0.5), Twist(0.1, 0, 0, 1e-9, 0, 0),
                         Twist(0, 0, 0, 0, 0, 0), Twist(1, 1, 1, 0, 0, 3.0)}) {
    EXPECT_NEAR((SE3::Exp(xi).Log() - xi).norm(), 0.0, 1e-9) << xi.transpose();
  }
}

TEST(SE3, ExpOfPureTranslationAndPureRotation) {
  const SE3 T = SE3::Exp(Twist(1, 2, 3, 0, 0, 0));
  EXPECT_NEAR((T.translation() - Vec3(1, 2, 3)).norm(), 0.0, 1e-12);
  const SE3 R = SE3::Exp(Twist(0, 0, 0, 0, M_PI / 2, 0));
  // 90 degrees about y maps z onto x.
  EXPECT_NEAR((R * Vec3(0, 0, 1) - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(R.angle(), M_PI / 2, 1e-12);
}

TEST(SE3, AngleIsShortestRotation) {
  EXPECT_NEAR(SE3::Exp(Twist(0, 0, 0, 0, 0, -0.7)).angle(), 0.7, 1e-12);
  EXPECT_NEAR(SE3::Exp(Twist(0, 0, 0, 0, 0, 2 * M_PI - 0.5)).angle(), 0.5, 1e-9);
}

TEST(SE3, InterpolateHitsEndpointsAndMidpoint) {
  const SE3 a = SE3::Exp(Twist(0, 0, 0, 0, 0, 0)), b = SE3::Exp(Twist(2, 0, 0, 0, 0.4, 0));
  EXPECT_TRUE(Interpolate(a, b, 0.0).isApprox(a));
  EXPECT_TRUE(Interpolate(a, b, 1.0).isApprox(b));
  const SE3 mid = Interpolate(a, b, 0.5);
  EXPECT_TRUE((mid * mid).isApprox(b, 1e-9));  // a = identity: the midpoint is the square root
}

TEST(SE3, FromMatrixReorthonormalises) {
  Mat4 T = SE3::Exp(Twist(1, 2, 3, 0.2, 0.1, -0.3)).matrix();
  T(0, 0) += 1e-6;  // as read from a text file with rounding
  const SE3 pose = SE3::FromMatrix(T);
  EXPECT_NEAR((pose.rotationMatrix() * pose.rotationMatrix().transpose() - Mat3::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((pose.translation() - Vec3(T(0, 3), T(1, 3), T(2, 3))).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace dslam
