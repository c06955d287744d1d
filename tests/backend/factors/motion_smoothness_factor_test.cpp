#include "backend/factors/motion_smoothness_factor.h"

#include <gtest/gtest.h>

#include <memory>

#include "backend/factor_graph.h"
#include "backend/factors/pose_manifold.h"
#include "support/factor_checks.h"

namespace dslam {
namespace {

TEST(MotionSmoothnessFactor, ZeroResidualForEqualMotions) {
  const SE3 H = SE3::Exp(test::SmallTwist(5.0));
  std::unique_ptr<ceres::CostFunction> cost(MotionSmoothnessFactor::Create(Vec6::Constant(0.1)));
  auto a = test::ToBlock(H), b = test::ToBlock(H);
  EXPECT_LT(test::MaxAbs(test::Evaluate(*cost, {a.data(), b.data()})), 1e-12);
}

TEST(MotionSmoothnessFactor, ResidualIsWhitenedLogOfChange) {
  const SE3 H = test::SomePose();
  const Vec6 change = test::SmallTwist(1.5);
  std::unique_ptr<ceres::CostFunction> cost(MotionSmoothnessFactor::Create(Vec6::Constant(0.25)));
  auto a = test::ToBlock(H), b = test::ToBlock(H * SE3::Exp(change));
  const auto r = test::Evaluate(*cost, {a.data(), b.data()});
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r[i], change[i] / 0.25, 1e-9);
}

TEST(MotionSmoothnessFactor, EqualWorldMotionsAboutDifferentAnchorsAreSmooth) {
  const SE3 H_world = SE3::Exp(test::SmallTwist(5.0));
  const Vec3 anchor_prev(200.0, 1.0, 400.0), anchor_curr(200.5, 1.0, 401.2);
  std::unique_ptr<ceres::CostFunction> cost(MotionSmoothnessFactor::Create(Vec6::Constant(0.1), anchor_prev, anchor_curr));
  auto a = MotionVariable::AnchorBlock(H_world, anchor_prev), b = MotionVariable::AnchorBlock(H_world, anchor_curr);
  EXPECT_LT(test::MaxAbs(test::Evaluate(*cost, {a.data(), b.data()})), 1e-9);
  // A change of the object's own motion shows the same, wherever the object is.
  const Vec6 change = test::SmallTwist(1.0);
  auto c = MotionVariable::AnchorBlock(H_world, anchor_prev);
  PoseBlock d;
  PoseToBlock(BlockToPose(c.data()) * SE3::Exp(change), d.data());
  std::unique_ptr<ceres::CostFunction> same_anchor(MotionSmoothnessFactor::Create(Vec6::Constant(0.1), anchor_prev, anchor_prev));
  const auto r = test::Evaluate(*same_anchor, {c.data(), d.data()});
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r[i], change[i] / 0.1, 1e-8);
  test::ExpectJacobiansMatchNumeric(*cost, {a.data(), b.data()}, 1e-5);
}

TEST(MotionSmoothnessFactor, JacobianMatchesNumeric) {
  std::unique_ptr<ceres::CostFunction> cost(MotionSmoothnessFactor::Create(Vec6::Constant(0.1)));
  auto a = test::ToBlock(SE3::Exp(test::SmallTwist(5.0))), b = test::ToBlock(SE3::Exp(test::SmallTwist(7.0)));
  test::ExpectJacobiansMatchNumeric(*cost, {a.data(), b.data()});
}

TEST(MotionSmoothnessFactor, SecondMotionConvergesToFirst) {
  const SE3 H = SE3::Exp(test::SmallTwist(5.0));
  auto a = test::ToBlock(H), b = test::ToBlock(H * SE3::Exp(test::SmallTwist(3.0)));
  ceres::Problem problem;
  problem.AddParameterBlock(a.data(), kPoseBlockSize, NewPoseManifold());
  problem.AddParameterBlock(b.data(), kPoseBlockSize, NewPoseManifold());
  problem.SetParameterBlockConstant(a.data());
  problem.AddResidualBlock(MotionSmoothnessFactor::Create(Vec6::Constant(0.1)), nullptr, a.data(), b.data());
  ASSERT_TRUE(test::Solve(&problem));
  EXPECT_TRUE(BlockToPose(b.data()).isApprox(H, 1e-8));
}

}  // namespace
}  // namespace dslam
