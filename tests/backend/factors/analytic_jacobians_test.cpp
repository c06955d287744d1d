// The analytic residuals and Jacobians both solvers use against Ceres autodiff of the reference
// functors (tests/support/reference_point_factors.h), mapped through the same tangent perturbation
// (q * Exp(phi), t + dt); and the Ceres cost functions built on them against the same reference.
#include "backend/factors/analytic_jacobians.h"

#include <gtest/gtest.h>

#include "backend/factors/point_measurement_factor.h"
#include "backend/factors/point_motion_factor.h"
#include "support/factor_checks.h"
#include "support/reference_point_factors.h"

namespace dslam {
namespace {

using RowJ = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;

RowJ Ambient(const std::vector<double>& j, int cols) { return Eigen::Map<const RowJ>(j.data(), 3, cols); }

TEST(AnalyticJacobians, PointMeasurementMatchesAutodiff) {
  const SE3 T(RotationExp(Vec3(0.3, -0.2, 0.5)), Vec3(1.0, -2.0, 0.5));
  const Vec3 z(0.4, -0.3, 8.0), sigma(0.02, 0.03, 0.05), l(2.0, -1.0, 9.0);
  PoseBlock block;
  PoseToBlock(T, block.data());
  std::array<double, 3> point{l.x(), l.y(), l.z()};
  std::unique_ptr<ceres::CostFunction> cost(test::ReferencePointMeasurement::Create(z, sigma));
  std::vector<std::vector<double>> jac;
  const auto r_auto = test::Evaluate(*cost, {block.data(), point.data()}, &jac);

  Mat36 J_pose;
  Mat3 J_point;
  const Vec3 r = PointMeasurementResidual(T.rotationMatrix(), T.translation(), l, z, sigma.cwiseInverse(), &J_pose, &J_point);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], r_auto[i], 1e-12);
  const Mat36 J_pose_auto = Ambient(jac[0], 7) * PoseBlockPlusJacobian(block.data());
  EXPECT_TRUE(J_pose.isApprox(J_pose_auto, 1e-9)) << J_pose << "\n" << J_pose_auto;
  EXPECT_TRUE(J_point.isApprox(Ambient(jac[1], 3), 1e-12));
}

TEST(AnalyticJacobians, PointMotionMatchesAutodiff) {
  const SE3 H(RotationExp(Vec3(0.05, 0.2, -0.1)), Vec3(0.8, 0.1, -0.3));
  const Vec3 anchor(3.0, 1.0, 12.0), prev(3.5, 0.7, 12.4), curr(4.2, 0.8, 12.1);
  PoseBlock block;
  PoseToBlock(H, block.data());
  std::array<double, 3> a{prev.x(), prev.y(), prev.z()}, b{curr.x(), curr.y(), curr.z()};
  const double sigma = 0.005;
  std::unique_ptr<ceres::CostFunction> cost(test::ReferencePointMotion::Create(sigma, anchor));
  std::vector<std::vector<double>> jac;
  const auto r_auto = test::Evaluate(*cost, {a.data(), b.data(), block.data()}, &jac);

  Mat3 J_prev, J_curr;
  Mat36 J_motion;
  const Vec3 r = PointMotionResidual(H.rotationMatrix(), H.translation(), anchor, prev, curr,
                                     Mat3::Identity() / sigma, &J_prev, &J_curr, &J_motion);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], r_auto[i], 1e-9);
  EXPECT_TRUE(J_prev.isApprox(Ambient(jac[0], 3), 1e-12));
  EXPECT_TRUE(J_curr.isApprox(Ambient(jac[1], 3), 1e-12));
  const Mat36 J_motion_auto = Ambient(jac[2], 7) * PoseBlockPlusJacobian(block.data());
  EXPECT_TRUE(J_motion.isApprox(J_motion_auto, 1e-9)) << J_motion << "\n" << J_motion_auto;
}

TEST(AnalyticJacobians, MarginalisedPredecessorUsesTheGivenWhitening) {
  const SE3 H(RotationExp(Vec3(0.0, 0.1, 0.0)), Vec3(0.5, 0.0, 0.0));
  Mat3 S;
  S << 50, 3, 0, 0, 40, 2, 0, 0, 30;
  const Vec3 anchor(1, 2, 3), prev(1.5, 2.0, 3.5), curr(2.0, 2.1, 3.4);
  Mat36 J_motion;
  Mat3 J_prev, J_curr;
  const Vec3 r = PointMotionResidual(H.rotationMatrix(), H.translation(), anchor, prev, curr, S, &J_prev, &J_curr, &J_motion);
  EXPECT_TRUE(r.isApprox(S * ((curr - anchor) - H.rotationMatrix() * (prev - anchor) - H.translation()), 1e-12));
  EXPECT_TRUE(J_curr.isApprox(S));
  // Numeric check of the motion Jacobian through the same tangent perturbation.
  const double h = 1e-7;
  for (int c = 0; c < 6; ++c) {
    Vec6 d = Vec6::Zero();
    d[c] = h;
    const Mat3 R1 = (H.rotation() * RotationExp(d.tail<3>())).toRotationMatrix();
    const Vec3 r1 = PointMotionResidual(R1, H.translation() + d.head<3>(), anchor, prev, curr, S, nullptr, nullptr, nullptr);
    EXPECT_TRUE(((r1 - r) / h).isApprox(J_motion.col(c), 1e-4)) << c;
  }
}

// The cost functions Ceres' batch solver uses hand over the analytic Jacobians in the blocks' seven
// coordinates: through the pose manifold's Plus Jacobian they are the reference's tangent Jacobians.
TEST(AnalyticJacobians, CeresCostFunctionsLiftToTheReferenceTangentJacobians) {
  const SE3 T(RotationExp(Vec3(-0.4, 0.7, 0.2)), Vec3(0.3, 1.0, -2.0));
  PoseBlock camera;
  PoseToBlock(T, camera.data());
  std::array<double, 3> l{1.5, -0.5, 11.0}, prev{1.2, -0.4, 10.5};
  const Vec3 z(0.2, 0.1, 9.0), sigma(0.03, 0.03, 0.2), anchor(1.0, 0.0, 10.0);

  std::unique_ptr<ceres::CostFunction> ours(PointMeasurementFactor::Create(z, sigma));
  std::unique_ptr<ceres::CostFunction> reference(test::ReferencePointMeasurement::Create(z, sigma));
  std::vector<std::vector<double>> J_ours, J_ref;
  const auto r_ours = test::Evaluate(*ours, {camera.data(), l.data()}, &J_ours);
  const auto r_ref = test::Evaluate(*reference, {camera.data(), l.data()}, &J_ref);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r_ours[i], r_ref[i], 1e-12);
  const Mat36 lifted = Ambient(J_ours[0], 7) * PoseBlockPlusJacobian(camera.data());
  EXPECT_TRUE(lifted.isApprox(Ambient(J_ref[0], 7) * PoseBlockPlusJacobian(camera.data()), 1e-10)) << lifted;
  EXPECT_TRUE(Ambient(J_ours[1], 3).isApprox(Ambient(J_ref[1], 3), 1e-12));

  ours.reset(PointMotionFactor::Create(0.01, anchor));
  reference.reset(test::ReferencePointMotion::Create(0.01, anchor));
  const auto m_ours = test::Evaluate(*ours, {prev.data(), l.data(), camera.data()}, &J_ours);
  const auto m_ref = test::Evaluate(*reference, {prev.data(), l.data(), camera.data()}, &J_ref);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m_ours[i], m_ref[i], 1e-9);
  for (int b = 0; b < 2; ++b) EXPECT_TRUE(Ambient(J_ours[b], 3).isApprox(Ambient(J_ref[b], 3), 1e-12)) << b;
  const Mat36 lifted_motion = Ambient(J_ours[2], 7) * PoseBlockPlusJacobian(camera.data());
  EXPECT_TRUE(lifted_motion.isApprox(Ambient(J_ref[2], 7) * PoseBlockPlusJacobian(camera.data()), 1e-10)) << lifted_motion;
}

// The lift itself: any tangent Jacobian comes back exactly through the Plus Jacobian.
TEST(AnalyticJacobians, AmbientJacobianTimesPlusJacobianIsTheTangentJacobian) {
  PoseBlock block;
  PoseToBlock(SE3(RotationExp(Vec3(1.1, -0.3, 0.6)), Vec3(4.0, 5.0, 6.0)), block.data());
  const Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Random();
  EXPECT_TRUE((AmbientJacobian<6>(J, block.data()) * PoseBlockPlusJacobian(block.data())).isApprox(J, 1e-12));
}

}  // namespace
}  // namespace dslam
