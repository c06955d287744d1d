#include "frontend/camera_motion.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Eigenvalues>

namespace dslam {
namespace {

struct Scene {
  std::vector<Vec3> p_prev;
  std::vector<Vec2> uv_curr;
};

// Points 5..30 m ahead seen from camera k-1, projected into camera k (with pixel noise and outliers).
Scene MakeScene(const SE3& T_prev_curr, const PinholeCamera& camera, int n, double outlier_fraction, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> px(0.0, 0.3);
  Scene s;
  while (static_cast<int>(s.p_prev.size()) < n) {
    const Vec3 p((u(rng) - 0.5) * 30.0, (u(rng) - 0.7) * 6.0, 5.0 + 25.0 * u(rng));
    const Vec3 q = T_prev_curr.inverse() * p;
    if (!camera.inImage(q)) continue;
    Vec2 uv = camera.project(q) + Vec2(px(rng), px(rng));
    if (u(rng) < outlier_fraction) uv += Vec2(20.0 + 30.0 * u(rng), -15.0);
    s.p_prev.push_back(p);
    s.uv_curr.push_back(uv);
  }
  return s;
}

const SE3 kTruth = SE3::Exp((Vec6() << 0.05, -0.01, 1.1, 0.002, 0.03, -0.001).finished());

TEST(EstimateCameraMotionPnp, RecoversTheMotionAndItsInliersDespiteOutliers) {
  const PinholeCamera camera;
  const Scene s = MakeScene(kTruth, camera, 300, 0.2, 1);
  const auto est = EstimateCameraMotionPnp(s.p_prev, s.uv_curr, camera, PnpParams{});
  ASSERT_TRUE(est);
  const Vec6 err = (kTruth.inverse() * est->T_prev_curr).Log();
  EXPECT_LT(err.head<3>().norm(), 0.02);
  EXPECT_LT(err.tail<3>().norm(), 0.05 * kDegToRad * 10);
  EXPECT_GT(est->inliers.size(), 220u);
  EXPECT_LT(est->inliers.size(), 250u);  // ~240 inliers of 300
  // Inlier reprojections constrain every direction of the motion.
  Eigen::SelfAdjointEigenSolver<Mat6> eig(est->information);
  EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
}

TEST(EstimateCameraMotionPnp, GivesUpWithTooFewPoints) {
  const PinholeCamera camera;
  const Scene s = MakeScene(kTruth, camera, 8, 0.0, 2);
  EXPECT_FALSE(EstimateCameraMotionPnp(s.p_prev, s.uv_curr, camera, PnpParams{}));
  EXPECT_THROW(EstimateCameraMotionPnp(s.p_prev, {}, camera, PnpParams{}), std::invalid_argument);
}

TEST(FuseCameraMotion, WeighsPnpAndOdometryByTheirInformation) {
  const PinholeCamera camera;
  const Scene s = MakeScene(kTruth, camera, 200, 0.0, 3);
  const auto pnp = EstimateCameraMotionPnp(s.p_prev, s.uv_curr, camera, PnpParams{});
  ASSERT_TRUE(pnp);
  OdometryMeasurement odometry;
  odometry.T_prev_curr = kTruth * SE3::Exp((Vec6() << 0.3, 0.0, 0.0, 0.0, 0.0, 0.0).finished());
  odometry.sigma = Vec6::Constant(1e-6);  // near-certain odometry wins
  EXPECT_LT((FuseCameraMotion(*pnp, odometry).translation() - odometry.T_prev_curr.translation()).norm(), 1e-3);
  odometry.sigma = Vec6::Constant(100.0);  // useless odometry changes nothing
  EXPECT_LT((FuseCameraMotion(*pnp, odometry).translation() - pnp->T_prev_curr.translation()).norm(), 1e-3);
}

}  // namespace
}  // namespace dslam
