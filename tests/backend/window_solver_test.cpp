#include "backend/window_solver.h"

#include <gtest/gtest.h>

#include "backend/graph_builder.h"
#include "backend/graph_solver.h"
#include "backend/marginalisation.h"
#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

FactorGraph CityGraph(int frames, const BackendParams& params) {
  ScenarioOptions opt;
  opt.num_frames = frames;
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> labelled = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &labelled);
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  for (const auto& f : labelled) builder.addFrame(f);
  return graph;
}

TEST(WindowSolver, ReachesTheSameMinimumAsCeres) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph ceres_graph = CityGraph(8, params);
  FactorGraph ours = ceres_graph;
  SolveOptions batch;
  batch.last_frame = 7;
  batch.max_iterations = 100;
  batch.function_tolerance = 1e-12;
  SolveGraph(params, batch, &ceres_graph);
  WindowSolveOptions window;
  window.last_frame = 7;
  window.max_iterations = 100;
  window.function_tolerance = 1e-12;
  const WindowSolveSummary summary = SolveWindow(params, window, &ours);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  for (int k = 0; k < 8; ++k)
    EXPECT_TRUE(BlockToPose(ours.camera(k)).isApprox(BlockToPose(ceres_graph.camera(k)), 1e-6)) << k;
  ASSERT_FALSE(ours.motions.empty());
  for (const auto& [id, m] : ours.motions)
    EXPECT_TRUE(m.worldMotion().isApprox(ceres_graph.motions.at(id).worldMotion(), 1e-6)) << id;
}

TEST(WindowSolver, HeldCamerasDoNotMove) {
  BackendParams params;
  FactorGraph graph = CityGraph(5, params);
  const FactorGraph before = graph;
  WindowSolveOptions window;
  window.last_frame = 4;
  window.fix_cameras = true;
  SolveWindow(params, window, &graph);
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(BlockToPose(graph.camera(k)).isApprox(BlockToPose(before.camera(k)), 0.0));
}

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
  EXPECT_EQ(graph.first_stored_frame, 0);  // camera 0 stays as the next window's anchor
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

}  // namespace
}  // namespace dslam
