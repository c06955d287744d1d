#include "backend/marginalisation.h"

// A leaving camera's measurement of a landmark still observed: held as a robust factor on the landmark
// (camera at its final estimate), then folded into the landmark's prior.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "backend/graph_builder.h"
#include "support/final_estimates.h"

namespace dslam {
namespace {

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
  test::FinalEstimates sink;
};

TEST(MarginaliseLandmark, ALeavingMeasurementIsHeldAsARobustFactorOnTheLandmark) {
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
TEST(MarginaliseLandmark, HeldMeasurementsWeighOutliersAtTheCurrentEstimate) {
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

TEST(MarginaliseLandmark, ALeavingMeasurementBecomesTheLandmarksPriorAndTheCameraIsFinal) {
  BackendParams params;
  params.landmark_history_frames = 0;  // folded at once
  TwoFrameLandmark t(params);
  const FactorGraph& graph = t.graph;
  const test::FinalEstimates& sink = t.sink;
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

}  // namespace
}  // namespace dslam
