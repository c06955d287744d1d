#include "backend/marginalisation.h"

// What leaves the fixed-lag smoother's window: landmarks' measurements held and folded into their priors
// with the camera final, object points eliminated exactly into linear factors on what they touched.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <memory>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/odometry_factor.h"
#include "backend/factors/pose_prior_factor.h"
#include "backend/graph_builder.h"
#include "backend/window_solver.h"
#include "support/city_graph.h"

namespace dslam {
namespace {

using test::CityGraph;

struct Recorder : EstimateSink {
  void cameraFinal(int frame, const SE3&) override { cameras.push_back(frame); }
  void motionFinal(const ObjectMotionEstimate& m) override { motions.push_back(m); }
  void pointFinal(const PointEstimate& p) override { points.push_back(p); }
  std::vector<int> cameras;
  std::vector<ObjectMotionEstimate> motions;
  std::vector<PointEstimate> points;
};

// Two frames seeing landmark 7; frame 0 leaves the window.
struct TwoFrameLandmark {
  explicit TwoFrameLandmark(const BackendParams& params) : builder(params, BuilderOptions{}, &graph) {
    FrameMeasurement f0, f1;
    f0.static_points = {{7, landmark}};
    f1.frame_index = 1;
    f1.odometry = OdometryMeasurement{T1, Vec6::Constant(0.01)};
    f1.static_points = {{7, T1.inverse() * landmark}};
    builder.addFrame(f0);
    builder.addFrame(f1);
    MarginaliseCameraFrame(params, 0, &graph, &sink);
  }
  const SE3 T1{RotationExp(Vec3(0.0, 0.1, 0.0)), Vec3(0.5, 0.0, 1.0)};
  const Vec3 landmark{1.0, -0.5, 10.0};
  FactorGraph graph;
  GraphBuilder builder;
  Recorder sink;
};

TEST(Marginalisation, ALeavingMeasurementIsHeldAsARobustFactorOnTheLandmark) {
  BackendParams params;  // landmark_history_frames > 0
  TwoFrameLandmark t(params);
  ASSERT_EQ(t.graph.points.size(), 1u);
  const PointVariable& p = t.graph.points.begin()->second;
  EXPECT_EQ(p.prior_info.trace(), 0.0);
  ASSERT_EQ(p.held.size(), 1u);
  EXPECT_EQ(p.held[0].frame, 0);
  EXPECT_TRUE(p.held[0].p_world.isApprox(t.landmark, 1e-12));  // camera 0 at the identity
  EXPECT_TRUE(p.hasPrior());
}

// A held measurement's Huber weight is that of the landmark's current estimate; folded, it keeps the
// weight it has then.
TEST(Marginalisation, HeldMeasurementsWeighOutliersAtTheCurrentEstimate) {
  const HuberLoss huber{1.0};
  const double sigma = 0.02;
  PointVariable p;
  const Vec3 x(1.0, 2.0, 10.0);
  const Mat3 A = Mat3::Identity() / sigma;
  p.held.push_back({A, x, 0});                         // agrees with x
  p.held.push_back({A, x + Vec3(0.0, 0.0, 0.5), 1});   // 25 sigma away
  Mat3 info;
  Vec3 gradient;
  p.priorNormalEquations(x, huber, &info, &gradient);
  const double w_outlier = huber.weight(25.0 * 25.0);  // 1/25
  EXPECT_NEAR(info(0, 0), (1.0 + w_outlier) / (sigma * sigma), 1e-6);
  EXPECT_NEAR(gradient.z(), -w_outlier * 0.5 / (sigma * sigma), 1e-6);
  EXPECT_NEAR(p.priorCost(x, huber), 0.5 * huber.rho(625.0), 1e-9);
  // Seen from a point next to the outlier, the outlier is the good one: weights follow the estimate.
  p.priorNormalEquations(x + Vec3(0.0, 0.0, 0.5), huber, &info, &gradient);
  EXPECT_NEAR(info(0, 0), (1.0 + w_outlier) / (sigma * sigma), 1e-6);
  p.foldOldestHeld(x, huber);
  ASSERT_EQ(p.held.size(), 1u);
  EXPECT_EQ(p.held[0].frame, 1);
  EXPECT_TRUE(p.prior_info.isApprox(A.transpose() * A, 1e-12));
  EXPECT_TRUE(p.prior_info.ldlt().solve(p.prior_info_vec).isApprox(x, 1e-12));
}

TEST(Marginalisation, ALeavingMeasurementBecomesTheLandmarksPriorAndTheCameraIsFinal) {
  BackendParams params;
  params.landmark_history_frames = 0;  // folded at once
  TwoFrameLandmark t(params);
  const FactorGraph& graph = t.graph;
  const Recorder& sink = t.sink;
  ASSERT_EQ(sink.cameras, std::vector<int>{0});
  ASSERT_EQ(sink.points.size(), 1u);
  EXPECT_EQ(sink.points[0].track_id, 7);
  ASSERT_EQ(graph.points.size(), 1u);  // still seen by frame 1
  const PointVariable& p = graph.points.begin()->second;
  // Camera 0 at the identity: information diag(1/sigma^2), mean at the measured point.
  const double w = 1.0 / (params.noise.point_sigma_m * params.noise.point_sigma_m);
  EXPECT_TRUE(p.prior_info.isApprox(w * Mat3::Identity(), 1e-12));
  EXPECT_TRUE(p.prior_info.ldlt().solve(p.prior_info_vec).isApprox(t.landmark, 1e-12));
  EXPECT_TRUE(p.held.empty());
  EXPECT_TRUE(graph.frame(0).measurements.empty());
  EXPECT_EQ(graph.first_stored_frame, 0);  // camera 0 stays stored until the next camera leaves
}

// Camera 0 leaves with landmark 8, which only it still sees (and which carries a prior from cameras before
// it); landmark 7 is still seen by camera 1. What remains must be the Schur complement, onto camera 1,
// of the Gauss-Newton system of camera 0's factors (first-camera prior, odometry, landmark 8's prior and
// measurement), here from numeric differences of the factors' residuals.
TEST(Marginalisation, ALeavingCameraLeavesTheSchurComplementOfItsFactorsOnTheNextCamera) {
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

  Recorder sink;
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

TEST(Marginalisation, ObjectPointsLeaveAsLinearFactorsThatKeepTheirCamera) {
  BackendParams params;
  params.default_mode = MotionMode::kPerStep;
  FactorGraph graph = CityGraph(6, params);
  const int ternaries_before = static_cast<int>(graph.frame(3).point_motions.size());
  ASSERT_GT(ternaries_before, 10);
  Recorder sink;
  for (int m = 0; m <= 2; ++m) MarginaliseObjectFrame(params, 10.0, m, &graph, &sink);
  // Every ternary factor from a point of frame 2 became a linear factor on (camera 2, successor, motion).
  for (const auto& pm : graph.frame(3).point_motions) EXPECT_TRUE(graph.points.count(pm.prev_point_var)) << pm.prev_point_var;
  ASSERT_EQ(static_cast<int>(graph.frame(3).linear_factors.size()), ternaries_before);
  for (const auto& lf : graph.frame(3).linear_factors) {
    EXPECT_EQ(lf.camera_frame, 2);
    EXPECT_GT(lf.J.leftCols<6>().norm(), 0.0);   // the camera keeps the object's constraint
    EXPECT_GT(lf.J.middleCols<3>(6).norm(), 0.0);
    EXPECT_GT(lf.J.rightCols<6>().norm(), 0.0);
    EXPECT_TRUE(lf.r0.allFinite());
    EXPECT_TRUE(graph.points.count(lf.point_var));
    EXPECT_TRUE(graph.motions.count(lf.motion_var));
  }
  EXPECT_TRUE(graph.frame(2).linear_factors.empty());
  for (const auto& [id, var] : graph.points) EXPECT_FALSE(var.object_id >= 0 && var.first_frame == 2 && var.last_frame == 2);
  // Transitions into frames 1 and 2 are final; those into 3 kept their centroid.
  ASSERT_FALSE(sink.motions.empty());
  for (const auto& m : sink.motions) EXPECT_LE(m.frame, 2);
  for (const auto& tr : graph.transitions) {
    EXPECT_GT(tr.frame, 2);
    if (tr.frame == 3) {
      EXPECT_TRUE(tr.centroid_prev_world.has_value());
    }
  }
  for (const auto& [id, m] : graph.motions) EXPECT_GT(m.last_frame, 2);
  // The solver accepts the converted graph.
  WindowSolveOptions window;
  window.first_frame = 1;
  window.last_frame = 5;
  const WindowSolveSummary summary = SolveWindow(params, window, &graph);
  EXPECT_LE(summary.final_cost, summary.initial_cost);
  // When camera 2 leaves the camera window it is held in those factors at its final value.
  MarginaliseCameraFrame(params, 0, &graph, &sink);
  MarginaliseCameraFrame(params, 1, &graph, &sink);
  MarginaliseCameraFrame(params, 2, &graph, &sink);
  for (const auto& lf : graph.frame(3).linear_factors) {
    EXPECT_EQ(lf.camera_frame, -1);
    EXPECT_EQ(lf.J.leftCols<6>().norm(), 0.0);
  }
  window.first_frame = 3;
  const WindowSolveSummary after = SolveWindow(params, window, &graph);
  EXPECT_LE(after.final_cost, after.initial_cost);
}


// Eliminating an object point is exact: the linear factor it leaves has the information matrix, vector and
// constant of the Schur complement of the point out of its measurement and its ternary factor, computed
// here densely from the normal equations (the smoother rotates the point out by QR instead).
TEST(Marginalisation, AnObjectPointLeavesTheSchurComplementOfItsFactors) {
  BackendParams params;
  params.default_mode = MotionMode::kPerStep;
  params.noise.huber_delta = 1e6;  // every weight 1: the factors are plain least squares here
  const SE3 H(RotationExp(Vec3(0.0, 0.08, 0.0)), Vec3(0.6, 0.0, 0.3));
  const SE3 T1(RotationExp(Vec3(0.0, 0.02, 0.0)), Vec3(0.0, 0.0, 1.0));
  FrameMeasurement f0, f1;
  f1.frame_index = 1;
  f1.odometry = OdometryMeasurement{T1, Vec6::Constant(0.01)};
  ObjectObservation a, b;
  a.object_id = b.object_id = 5;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p(2.0 + 0.4 * (i % 4), 0.3 * (i / 4), 12.0 + 0.2 * i);
    a.points.push_back({100 + i, p});
    b.points.push_back({100 + i, T1.inverse() * (H * p)});
  }
  f0.objects = {a};
  f1.objects = {b};
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  builder.addFrame(f0);
  builder.addFrame(f1);
  ASSERT_EQ(graph.frame(1).point_motions.size(), 8u);
  // Away from the optimum, so that the gradient and the constant are not zero.
  int n = 0;
  for (auto& [id, var] : graph.points) {
    ++n;
    var.p_world[0] += 0.01 * (n % 3);
    var.p_world[2] -= 0.02 * (n % 2);
  }
  graph.camera(0)[4] += 0.03;
  const FactorGraph before = graph;
  Recorder sink;
  MarginaliseObjectFrame(params, 10.0, 0, &graph, &sink);
  const auto& linear = graph.frame(1).linear_factors;
  ASSERT_EQ(linear.size(), 8u);
  EXPECT_TRUE(graph.frame(1).point_motions.empty());

  const double* cam = before.camera(0);
  const Mat3 R = BlockRotationMatrix(cam);
  const Vec3 t = BlockTranslation(cam);
  const Mat3 S = Mat3::Identity() / params.noise.motion_sigma_m;
  for (const auto& pm : before.frame(1).point_motions) {
    const PointVariable& point = before.points.at(pm.prev_point_var);
    const PointMeasurementEntry* meas = nullptr;
    for (const auto& e : before.frame(0).measurements)
      if (e.point_var == pm.prev_point_var) meas = &e;
    ASSERT_NE(meas, nullptr);
    const MotionVariable& motion = before.motions.at(pm.motion_var);
    // Stacked whitened rows over x = [point | camera 0 | successor | motion], residual beside.
    Eigen::Matrix<double, 6, 18> A = Eigen::Matrix<double, 6, 18>::Zero();
    Vec6 r;
    Mat36 J_cam, J_motion;
    Mat3 J_point, J_prev, J_curr;
    r.head<3>() = PointMeasurementResidual(R, t, point.position(), meas->z_camera, meas->sigma_m.cwiseInverse(), &J_cam,
                                           &J_point);
    A.block<3, 3>(0, 0) = J_point;
    A.block<3, 6>(0, 3) = J_cam;
    r.tail<3>() = PointMotionResidual(BlockRotationMatrix(motion.H_anchor.data()), BlockTranslation(motion.H_anchor.data()),
                                      motion.anchor_world, point.position(),
                                      before.points.at(pm.curr_point_var).position(), S, &J_prev, &J_curr, &J_motion);
    A.block<3, 3>(3, 0) = J_prev;
    A.block<3, 3>(3, 9) = J_curr;
    A.block<3, 6>(3, 12) = J_motion;
    const Eigen::Matrix<double, 18, 18> info = A.transpose() * A;
    const Eigen::Matrix<double, 18, 1> g = A.transpose() * r;
    const Mat3 info_pp_inv = info.topLeftCorner<3, 3>().inverse();
    const Eigen::Matrix<double, 15, 15> schur_info =
        info.bottomRightCorner<15, 15>() - info.block<15, 3>(3, 0) * info_pp_inv * info.block<3, 15>(0, 3);
    const Eigen::Matrix<double, 15, 1> schur_g = g.tail<15>() - info.block<15, 3>(3, 0) * info_pp_inv * g.head<3>();
    const double schur_c = r.squaredNorm() - g.head<3>().dot(info_pp_inv * g.head<3>());

    const LinearPointFactor* lf = nullptr;
    for (const auto& f : linear)
      if (f.point_var == pm.curr_point_var) lf = &f;
    ASSERT_NE(lf, nullptr);
    EXPECT_EQ(lf->camera_frame, 0);
    EXPECT_EQ(lf->motion_var, pm.motion_var);
    const double scale = schur_info.norm();
    EXPECT_LT((lf->J.transpose() * lf->J - schur_info).norm(), 1e-9 * scale);
    EXPECT_LT((lf->J.transpose() * lf->r0 - schur_g).norm(), 1e-9 * std::max(1.0, schur_g.norm()));
    EXPECT_NEAR(lf->r0.squaredNorm(), schur_c, 1e-9 * std::max(1.0, r.squaredNorm()));
    EXPECT_GT(schur_g.norm(), 0.0);
    // Its linearisation point is where the point left: the estimates of camera 0, successor and motion then.
    EXPECT_EQ(PoseBlockMinus(lf->camera_lin.data(), cam).norm(), 0.0);
    EXPECT_EQ((lf->point_lin - before.points.at(pm.curr_point_var).position()).norm(), 0.0);
    EXPECT_EQ(PoseBlockMinus(lf->motion_lin.data(), motion.H_anchor.data()).norm(), 0.0);
  }
  // The points of frame 0 went to the sink as final.
  EXPECT_EQ(sink.points.size(), 8u);
}

}  // namespace
}  // namespace dslam
