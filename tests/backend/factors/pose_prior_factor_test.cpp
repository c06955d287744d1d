#include "backend/factors/pose_prior_factor.h"

#include <gtest/gtest.h>

#include <memory>

#include "backend/factors/pose_manifold.h"
#include "support/factor_checks.h"

namespace dslam {
namespace {

TEST(PosePriorFactor, ZeroResidualAtPrior) {
  const SE3 T = test::SomePose();
  std::unique_ptr<ceres::CostFunction> cost(PosePriorFactor::Create(T, Vec6::Constant(1e-3)));
  auto block = test::ToBlock(T);
  EXPECT_LT(test::MaxAbs(test::Evaluate(*cost, {block.data()})), 1e-9);
}

TEST(PosePriorFactor, ResidualIsWhitenedLog) {
  const Vec6 xi = test::SmallTwist(2.0);
  std::unique_ptr<ceres::CostFunction> cost(PosePriorFactor::Create(SE3::Identity(), Vec6::Constant(0.5)));
  auto block = test::ToBlock(SE3::Exp(xi));
  const auto r = test::Evaluate(*cost, {block.data()});
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r[i], xi[i] / 0.5, 1e-9);
}

TEST(PosePriorFactor, JacobianMatchesNumeric) {
  std::unique_ptr<ceres::CostFunction> cost(PosePriorFactor::Create(test::SomePose(), Vec6::Constant(0.1)));
  auto block = test::ToBlock(test::SomePose(1.4));
  test::ExpectJacobiansMatchNumeric(*cost, {block.data()});
}

TEST(PosePriorFactor, ConvergesFromPerturbedStart) {
  const SE3 prior = test::SomePose();
  auto block = test::ToBlock(prior * SE3::Exp(test::SmallTwist(8.0)));
  ceres::Problem problem;
  problem.AddParameterBlock(block.data(), kPoseBlockSize, NewPoseManifold());
  problem.AddResidualBlock(PosePriorFactor::Create(prior, Vec6::Constant(1e-3)), nullptr, block.data());
  ASSERT_TRUE(test::Solve(&problem));
  EXPECT_TRUE(BlockToPose(block.data()).isApprox(prior, 1e-8));
}

}  // namespace
}  // namespace dslam
