#include "geometry/velocity.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(ObjectVelocity, PureTranslationIsTheTranslation) {
  const SE3 H(Eigen::Quaterniond::Identity(), Vec3(0.5, 0.0, 1.0));
  EXPECT_NEAR((ObjectVelocityPerFrame(H, Vec3(10, 1, 20)) - Vec3(0.5, 0.0, 1.0)).norm(), 0.0, 1e-12);
}

TEST(ObjectVelocity, RotationAboutTheCentroidHasZeroVelocity) {
  // H = rotation of 0.3 rad about the vertical axis through c: t = c - R c.
  const Vec3 c(4.0, 1.0, 12.0);
  const Mat3 R = Eigen::AngleAxisd(0.3, Vec3::UnitY()).toRotationMatrix();
  const SE3 H(R, c - R * c);
  EXPECT_NEAR(ObjectVelocityPerFrame(H, c).norm(), 0.0, 1e-12);
}

TEST(ObjectVelocity, EqualsDisplacementOfTheCentroidPoint) {
  const Mat3 R = Eigen::AngleAxisd(0.1, Vec3::UnitY()).toRotationMatrix();
  const SE3 H(R, Vec3(1.0, 0.0, 2.0));
  const Vec3 c(3.0, 0.5, 15.0);
  EXPECT_NEAR((ObjectVelocityPerFrame(H, c) - (H * c - c)).norm(), 0.0, 1e-12);
}

TEST(ObjectVelocity, SpeedUsesTheFrameRate) {
  // 1.2 m per frame at 10 Hz = 12 m/s = 43.2 km/h.
  EXPECT_NEAR(SpeedMps(Vec3(0.0, 0.0, 1.2), 10.0), 12.0, 1e-12);
  EXPECT_NEAR(SpeedMps(Vec3(0.0, 0.0, 1.2), 10.0) * kMpsToKmh, 43.2, 1e-9);
}

}  // namespace
}  // namespace dslam
