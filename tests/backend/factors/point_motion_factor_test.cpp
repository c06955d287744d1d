#include "backend/factors/point_motion_factor.h"

#include <gtest/gtest.h>

#include <memory>

#include "backend/factor_graph.h"
#include "backend/factors/pose_manifold.h"
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

TEST(PointMotionFactor, AnchoredMotionGivesTheWorldFrameResidual) {
  // Far from the world origin, with H stored about an anchor near the object.
  const SE3 H_world = SE3::Exp(test::SmallTwist(5.0));
  const Vec3 anchor(300.0, 1.0, 650.0);
  const Vec3 prev(301.0, 0.5, 652.0), curr = H_world * prev + Vec3(0.01, -0.02, 0.03);
  std::unique_ptr<ceres::CostFunction> world(PointMotionFactor::Create(0.01));
  std::unique_ptr<ceres::CostFunction> anchored(PointMotionFactor::Create(0.01, anchor));
  double a[3] = {prev.x(), prev.y(), prev.z()}, b[3] = {curr.x(), curr.y(), curr.z()};
  auto h_world = test::ToBlock(H_world);
  auto h_anchor = MotionVariable::AnchorBlock(H_world, anchor);
  const auto r_world = test::Evaluate(*world, {a, b, h_world.data()});
  const auto r_anchor = test::Evaluate(*anchored, {a, b, h_anchor.data()});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r_world[i], r_anchor[i], 1e-6);
  EXPECT_NEAR(r_anchor[2], 3.0, 1e-6);
  test::ExpectJacobiansMatchNumeric(*anchored, {a, b, h_anchor.data()}, 1e-5);
  // Round trip of the anchored storage.
  MotionVariable var;
  var.anchor_world = anchor;
  var.H_anchor = h_anchor;
  EXPECT_TRUE(var.worldMotion().isApprox(H_world, 1e-9));
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
