#include "backend/marginalisation.h"

// A per-frame object point leaving the object window: eliminated exactly into a linear factor on its
// camera, its successor and the motion into the successor's frame.

#include <gtest/gtest.h>

#include "backend/factors/analytic_jacobians.h"
#include "backend/graph_builder.h"
#include "backend/window_solver.h"
#include "support/city_graph.h"
#include "support/final_estimates.h"

namespace dslam {
namespace {

using test::CityGraph;

TEST(MarginaliseObjectPoint, ObjectPointsLeaveAsLinearFactorsThatKeepTheirCamera) {
  BackendParams params;
  params.default_mode = MotionMode::kPerStep;
  FactorGraph graph = CityGraph(6, params);
  const int ternaries_before = static_cast<int>(graph.frame(3).point_motions.size());
  ASSERT_GT(ternaries_before, 10);
  test::FinalEstimates sink;
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
TEST(MarginaliseObjectPoint, AnObjectPointLeavesTheSchurComplementOfItsFactors) {
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
  test::FinalEstimates sink;
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
