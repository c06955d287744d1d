#include "backend/marginalisation.h"

// A leaving camera: eliminated by a Schur complement (with the landmarks only it still measures) into a
// prior on the next camera, linearised where it was made.

#include <gtest/gtest.h>

#include <memory>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/odometry_factor.h"
#include "backend/factors/pose_prior_factor.h"
#include "backend/graph_builder.h"
#include "backend/window_solver.h"
#include "support/final_estimates.h"

namespace dslam {
namespace {

// Camera 0 leaves with landmark 8, which only it still sees (and which carries a prior from cameras before
// it); landmark 7 is still seen by camera 1. What remains must be the Schur complement, onto camera 1,
// of the Gauss-Newton system of camera 0's factors (first-camera prior, odometry, landmark 8's prior and
// measurement), here from numeric differences of the factors' residuals.
TEST(MarginaliseCamera, ALeavingCameraLeavesTheSchurComplementOfItsFactorsOnTheNextCamera) {
  BackendParams params;
  params.camera_prior_by_schur = true;
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  const SE3 T1{RotationExp(Vec3(0.02, 0.1, -0.03)), Vec3(0.5, 0.0, 1.0)};
  const Vec3 l7{1.0, -0.5, 10.0}, l8{-2.0, 0.3, 8.0};
  const OdometryMeasurement odometry{T1, (Vec6() << 0.02, 0.01, 0.05, 0.002, 0.004, 0.001).finished()};
  FrameMeasurement f0, f1;
  f0.static_points = {{7, l7}, {8, l8}};
  f1.frame_index = 1;
  f1.odometry = odometry;
  f1.static_points = {{7, T1.inverse() * l7}};
  builder.addFrame(f0);
  builder.addFrame(f1);
  ASSERT_EQ(graph.points.size(), 2u);
  graph.prior_sigma = Vec6::Constant(0.2);  // a loose first camera: landmark 8's prior moves it
  int var8 = -1;
  for (auto& [id, p] : graph.points)
    if (p.track_id == 8) var8 = id;
  ASSERT_GE(var8, 0);
  PointVariable& p8 = graph.points.at(var8);
  p8.prior_info = Vec3(400.0, 900.0, 100.0).asDiagonal();
  p8.prior_info_vec = p8.prior_info * (l8 + Vec3(0.1, -0.2, 0.3));
  const PointMeasurementEntry* m8 = nullptr;
  for (const auto& e : graph.frame(0).measurements)
    if (e.point_var == var8) m8 = &e;
  ASSERT_NE(m8, nullptr);

  // Residuals of camera 0's factors at the steps d = [camera 0 (6), camera 1 (6), landmark 8 (3)].
  const std::unique_ptr<ceres::CostFunction> prior(PosePriorFactor::Create(graph.T_world_camera0_prior, graph.prior_sigma));
  const std::unique_ptr<ceres::CostFunction> odo(OdometryFactor::Create(odometry.T_prev_curr, odometry.sigma));
  const Mat3 U8 = p8.prior_info.llt().matrixU();
  const Vec3 mean8 = p8.prior_info.ldlt().solve(p8.prior_info_vec);
  const PoseBlock cam0 = graph.camera_poses[0], cam1 = graph.camera_poses[1];
  auto residuals = [&](const Eigen::Matrix<double, 15, 1>& d) {
    PoseBlock c0, c1;
    PoseBlockPlus(cam0.data(), d.head<6>(), c0.data());
    PoseBlockPlus(cam1.data(), d.segment<6>(6), c1.data());
    const Vec3 l = p8.position() + d.tail<3>();
    Eigen::Matrix<double, 18, 1> r;
    const double* b0[1] = {c0.data()};
    prior->Evaluate(b0, r.data(), nullptr);
    const double* b01[2] = {c0.data(), c1.data()};
    odo->Evaluate(b01, r.data() + 6, nullptr);
    r.segment<3>(12) = U8 * (l - mean8);
    r.tail<3>() = PointMeasurementResidual(BlockRotationMatrix(c0.data()), BlockTranslation(c0.data()), l, m8->z_camera,
                                           m8->sigma_m.cwiseInverse(), nullptr, nullptr);
    return r;
  };
  Eigen::Matrix<double, 18, 15> J;
  const double h = 1e-6;
  for (int i = 0; i < 15; ++i) {
    Eigen::Matrix<double, 15, 1> d = Eigen::Matrix<double, 15, 1>::Zero();
    d[i] = h;
    const Eigen::Matrix<double, 18, 1> plus = residuals(d);
    d[i] = -h;
    J.col(i) = (plus - residuals(d)) / (2.0 * h);
  }
  const Eigen::Matrix<double, 18, 1> r = residuals(Eigen::Matrix<double, 15, 1>::Zero());
  // Order [camera 1 | camera 0, landmark 8] and eliminate the second part.
  Eigen::Matrix<double, 18, 15> A;
  A << J.middleCols<6>(6), J.leftCols<6>(), J.rightCols<3>();
  const Eigen::Matrix<double, 15, 15> H = A.transpose() * A;
  const Eigen::Matrix<double, 15, 1> b = A.transpose() * r;
  const Eigen::Matrix<double, 9, 9> Hll = H.bottomRightCorner<9, 9>();
  const Mat6 expected_info = H.topLeftCorner<6, 6>() - H.topRightCorner<6, 9>() * Hll.ldlt().solve(H.bottomLeftCorner<9, 6>());
  const Vec6 expected_gradient = b.head<6>() - H.topRightCorner<6, 9>() * Hll.ldlt().solve(b.tail<9>());

  test::FinalEstimates sink;
  MarginaliseCameraFrame(params, 0, &graph, &sink);
  ASSERT_TRUE(graph.camera_prior.has_value());
  const CameraPrior& cp = *graph.camera_prior;
  EXPECT_EQ(cp.frame, 1);
  EXPECT_FALSE(graph.frame(1).odometry.has_value());  // eliminated with camera 0
  EXPECT_TRUE(std::equal(cp.camera_lin.begin(), cp.camera_lin.end(), cam1.begin()));
  const Mat6 info = cp.R.transpose() * cp.R;
  EXPECT_LT((info - expected_info).cwiseAbs().maxCoeff(), 1e-6 * expected_info.cwiseAbs().maxCoeff());
  const Vec6 gradient = cp.R.transpose() * cp.residual(graph.camera(1));
  EXPECT_LT((gradient - expected_gradient).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, expected_gradient.cwiseAbs().maxCoeff()));
  EXPECT_GT(expected_gradient.norm(), 1.0);  // landmark 8's prior pulls: the check is not of zeros
  EXPECT_EQ(graph.points.count(var8), 0u);
  ASSERT_EQ(graph.points.size(), 1u);
  EXPECT_EQ(graph.points.begin()->second.held.size(), 1u);  // landmark 7 keeps camera 0's measurement

  // The window now starts at camera 1 with the prior in place of the odometry; the prior keeps its
  // linearisation point while the solve moves the camera.
  WindowSolveOptions solve;
  solve.first_frame = solve.last_frame = 1;
  const WindowSolveSummary summary = SolveWindow(params, solve, &graph);
  EXPECT_EQ(summary.num_residual_blocks, 3);  // the prior, landmark 7's measurement and its held one
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_TRUE(std::equal(graph.camera_prior->camera_lin.begin(), graph.camera_prior->camera_lin.end(), cam1.begin()));
  EXPECT_GT(PoseBlockMinus(graph.camera(1), cam1.data()).norm(), 1e-6);
}

}  // namespace
}  // namespace dslam
