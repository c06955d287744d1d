#include "backend/factors/odometry_factor.h"

#include <gtest/gtest.h>

#include <memory>

#include "backend/factors/pose_manifold.h"
#include "backend/factors/pose_prior_factor.h"
#include "support/factor_checks.h"

namespace dslam {
namespace {

TEST(OdometryFactor, ZeroResidualAtGroundTruth) {
  const SE3 T0 = test::SomePose(), T1 = test::SomePose(1.3);
  std::unique_ptr<ceres::CostFunction> cost(OdometryFactor::Create(T0.inverse() * T1, Vec6::Constant(0.01)));
  auto a = test::ToBlock(T0), b = test::ToBlock(T1);
  EXPECT_LT(test::MaxAbs(test::Evaluate(*cost, {a.data(), b.data()})), 1e-9);
}

TEST(OdometryFactor, ResidualIsWhitenedLogOfError) {
  // Measured identity, true increment Exp(xi): the residual is Log(Exp(xi)) / sigma = xi / sigma.
  const Vec6 xi = test::SmallTwist(1.0);
  const Vec6 sigma = (Vec6() << 0.1, 0.1, 0.1, 0.02, 0.02, 0.02).finished();
  std::unique_ptr<ceres::CostFunction> cost(OdometryFactor::Create(SE3::Identity(), sigma));
  auto a = test::ToBlock(SE3::Identity()), b = test::ToBlock(SE3::Exp(xi));
  const auto r = test::Evaluate(*cost, {a.data(), b.data()});
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r[i], xi[i] / sigma[i], 1e-9) << i;
}

TEST(OdometryFactor, JacobianMatchesNumeric) {
  std::unique_ptr<ceres::CostFunction> cost(
      OdometryFactor::Create(SE3::Exp(test::SmallTwist(3.0)), Vec6::Constant(0.05)));
  auto a = test::ToBlock(test::SomePose()), b = test::ToBlock(test::SomePose(1.2));
  test::ExpectJacobiansMatchNumeric(*cost, {a.data(), b.data()});
}

TEST(OdometryFactor, JacobianFiniteAtZeroError) {
  const SE3 T0 = test::SomePose(), T1 = test::SomePose(1.1);
  std::unique_ptr<ceres::CostFunction> cost(OdometryFactor::Create(T0.inverse() * T1, Vec6::Constant(0.05)));
  auto a = test::ToBlock(T0), b = test::ToBlock(T1);
  test::ExpectJacobiansMatchNumeric(*cost, {a.data(), b.data()}, 1e-5);
}

TEST(OdometryFactor, SecondPoseConvergesFromPerturbedStart) {
  const SE3 T0 = test::SomePose(), increment = SE3::Exp(test::SmallTwist(10.0));
  auto a = test::ToBlock(T0), b = test::ToBlock(T0 * increment * SE3::Exp(test::SmallTwist(4.0)));
  ceres::Problem problem;
  problem.AddParameterBlock(a.data(), kPoseBlockSize, NewPoseManifold());
  problem.AddParameterBlock(b.data(), kPoseBlockSize, NewPoseManifold());
  problem.AddResidualBlock(PosePriorFactor::Create(T0, Vec6::Constant(1e-4)), nullptr, a.data());
  problem.AddResidualBlock(OdometryFactor::Create(increment, Vec6::Constant(0.01)), nullptr, a.data(), b.data());
  ASSERT_TRUE(test::Solve(&problem));
  EXPECT_TRUE(BlockToPose(b.data()).isApprox(T0 * increment, 1e-7));
}

}  // namespace
}  // namespace dslam
