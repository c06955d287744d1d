#include "backend/factors/point_motion_factor.h"

#include <gtest/gtest.h>

#include <memory>

#include "support/factor_checks.h"

namespace dslam {
namespace {

TEST(PointMotionFactor, ZeroResidualAtGroundTruth) {
  const SE3 H = SE3::Exp(test::SmallTwist(5.0));
  const Vec3 prev(4.0, 1.0, 15.0), curr = H * prev;
  std::unique_ptr<ceres::CostFunction> cost(PointMotionFactor::Create(0.01));
  double a[3] = {prev.x(), prev.y(), prev.z()}, b[3] = {curr.x(), curr.y(), curr.z()};
  auto h = test::ToBlock(H);
  EXPECT_LT(test::MaxAbs(test::Evaluate(*cost, {a, b, h.data()})), 1e-9);
}

TEST(PointMotionFactor, ResidualIsWhitenedDisplacementError) {
  // Pure translation H = (I, t): residual = (b - a - t) / sigma.
  std::unique_ptr<ceres::CostFunction> cost(PointMotionFactor::Create(0.5));
  double a[3] = {1.0, 2.0, 3.0}, b[3] = {2.0, 2.0, 3.5};
  auto h = test::ToBlock(SE3(Eigen::Quaterniond::Identity(), Vec3(1.0, 0.0, 0.0)));
  const auto r = test::Evaluate(*cost, {a, b, h.data()});
  EXPECT_NEAR(r[0], 0.0, 1e-12);
  EXPECT_NEAR(r[1], 0.0, 1e-12);
  EXPECT_NEAR(r[2], 1.0, 1e-12);
}

TEST(PointMotionFactor, JacobianMatchesNumeric) {
  std::unique_ptr<ceres::CostFunction> cost(PointMotionFactor::Create(0.02));
  double a[3] = {4.0, 1.0, 15.0}, b[3] = {4.5, 0.9, 16.0};
  auto h = test::ToBlock(SE3::Exp(test::SmallTwist(4.0)));
  test::ExpectJacobiansMatchNumeric(*cost, {a, b, h.data()});
}

TEST(PointMotionFactor, MotionConvergesFromPerturbedStart) {
  // Fixed point pairs of a rigid body; only H is free.
  const SE3 H_true = SE3::Exp(test::SmallTwist(6.0));
  std::vector<std::array<double, 3>> prev, curr;
  for (const Vec3& p : {Vec3(1, 0, 10), Vec3(-1, 0.5, 11), Vec3(0.3, -0.6, 9.5), Vec3(2, 1, 12)}) {
    const Vec3 q = H_true * p;
    prev.push_back({p.x(), p.y(), p.z()});
    curr.push_back({q.x(), q.y(), q.z()});
  }
  auto h = test::ToBlock(H_true * SE3::Exp(test::SmallTwist(3.0)));
  ceres::Problem problem;
  problem.AddParameterBlock(h.data(), kPoseBlockSize, NewPoseManifold());
  for (size_t i = 0; i < prev.size(); ++i) {
    problem.AddResidualBlock(PointMotionFactor::Create(0.01), nullptr, prev[i].data(), curr[i].data(), h.data());
    problem.SetParameterBlockConstant(prev[i].data());
    problem.SetParameterBlockConstant(curr[i].data());
  }
  ASSERT_TRUE(test::Solve(&problem));
  EXPECT_TRUE(BlockToPose(h.data()).isApprox(H_true, 1e-7));
}

}  // namespace
}  // namespace dslam
