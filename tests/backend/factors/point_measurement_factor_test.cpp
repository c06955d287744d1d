#include "backend/factors/point_measurement_factor.h"

#include <gtest/gtest.h>

#include <memory>

#include "backend/factors/pose_manifold.h"
#include "support/factor_checks.h"

namespace dslam {
namespace {

TEST(PointMeasurementFactor, ZeroResidualAtGroundTruth) {
  const SE3 T_world_camera = test::SomePose();
  const Vec3 l_world(3.0, -1.0, 12.0);
  const Vec3 z = T_world_camera.inverse() * l_world;
  std::unique_ptr<ceres::CostFunction> cost(PointMeasurementFactor::Create(z, Vec3::Constant(0.02)));
  auto pose = test::ToBlock(T_world_camera);
  double l[3] = {l_world.x(), l_world.y(), l_world.z()};
  EXPECT_LT(test::MaxAbs(test::Evaluate(*cost, {pose.data(), l})), 1e-12);
}

TEST(PointMeasurementFactor, ResidualIsWhitenedError) {
  std::unique_ptr<ceres::CostFunction> cost(PointMeasurementFactor::Create(Vec3(1.0, 2.0, 10.0), Vec3(0.1, 0.2, 0.5)));
  auto pose = test::ToBlock(SE3::Identity());
  double l[3] = {1.1, 2.0, 9.0};
  const auto r = test::Evaluate(*cost, {pose.data(), l});
  EXPECT_NEAR(r[0], 1.0, 1e-9);
  EXPECT_NEAR(r[1], 0.0, 1e-9);
  EXPECT_NEAR(r[2], -2.0, 1e-9);
}

TEST(PointMeasurementFactor, JacobianMatchesNumeric) {
  std::unique_ptr<ceres::CostFunction> cost(PointMeasurementFactor::Create(Vec3(0.5, -0.2, 8.0), Vec3::Constant(0.05)));
  auto pose = test::ToBlock(test::SomePose());
  double l[3] = {2.0, 1.0, 9.0};
  test::ExpectJacobiansMatchNumeric(*cost, {pose.data(), l});
}

TEST(PointMeasurementFactor, PointConvergesFromPerturbedStart) {
  const SE3 T_world_camera = test::SomePose();
  const Vec3 l_true(3.0, -1.0, 12.0);
  auto pose = test::ToBlock(T_world_camera);
  double l[3] = {l_true.x() + 0.8, l_true.y() - 0.5, l_true.z() + 1.0};
  ceres::Problem problem;
  problem.AddParameterBlock(pose.data(), kPoseBlockSize, NewPoseManifold());
  problem.SetParameterBlockConstant(pose.data());
  problem.AddResidualBlock(PointMeasurementFactor::Create(T_world_camera.inverse() * l_true, Vec3::Constant(0.02)),
                           nullptr, pose.data(), l);
  ASSERT_TRUE(test::Solve(&problem));
  EXPECT_NEAR((Vec3(l[0], l[1], l[2]) - l_true).norm(), 0.0, 1e-8);
}

}  // namespace
}  // namespace dslam
