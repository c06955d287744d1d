#include "backend/graph_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "backend/factors/pose_block.h"
#include "backend/marginalisation.h"

namespace dslam {
namespace {

TEST(GraphBuilder, CamerasStartFromTheFrontEndsGuessElseFromTheOdometry) {
  const SE3 odometry(RotationExp(Vec3(0.0, 0.05, 0.0)), Vec3(0.1, 0.0, 1.0));
  const SE3 guess(RotationExp(Vec3(0.0, 0.04, 0.0)), Vec3(0.0, 0.0, 0.9));
  FrameMeasurement f0, f1, f2;
  f1.frame_index = 1;
  f1.odometry = OdometryMeasurement{odometry, Vec6::Constant(0.01)};
  f2 = f1;
  f2.frame_index = 2;
  f2.camera_motion_guess = guess;
  BackendParams params;
  FactorGraph graph;
  graph.T_world_camera0_prior = SE3(RotationExp(Vec3(0.1, 0.0, 0.0)), Vec3(5.0, 0.0, 0.0));
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  builder.addFrame(f0);
  builder.addFrame(f1);
  builder.addFrame(f2);
  const SE3 T0 = graph.T_world_camera0_prior;
  EXPECT_TRUE(BlockToPose(graph.camera(0)).isApprox(T0, 1e-12));
  EXPECT_TRUE(BlockToPose(graph.camera(1)).isApprox(T0 * odometry, 1e-12));
  EXPECT_TRUE(BlockToPose(graph.camera(2)).isApprox(T0 * odometry * guess, 1e-12));
  // The odometry is a factor either way; the guess is only a start.
  ASSERT_TRUE(graph.frame(2).odometry.has_value());
  EXPECT_TRUE(graph.frame(2).odometry->T_prev_curr.isApprox(odometry, 1e-12));
  EXPECT_FALSE(graph.frame(0).odometry.has_value());
}

TEST(GraphBuilder, AStaticPointIsOneVariableSeenByEveryFrame) {
  BackendParams params;
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  const Vec3 landmark(1.0, -0.5, 10.0);
  for (int k = 0; k < 3; ++k) {
    FrameMeasurement f;
    f.frame_index = k;
    if (k > 0) f.odometry = OdometryMeasurement{SE3(Mat3::Identity(), Vec3(0.0, 0.0, 1.0)), Vec6::Constant(0.01)};
    f.static_points = {{7, landmark - Vec3(0.0, 0.0, k)}};
    builder.addFrame(f);
  }
  ASSERT_EQ(graph.points.size(), 1u);
  const PointVariable& p = graph.points.begin()->second;
  EXPECT_EQ(p.object_id, -1);
  EXPECT_EQ(p.first_frame, 0);
  EXPECT_EQ(p.last_frame, 2);
  EXPECT_TRUE(p.position().isApprox(landmark, 1e-12));  // from its first measurement and camera
  for (int k = 0; k < 3; ++k) EXPECT_EQ(graph.frame(k).measurements.size(), 1u) << k;
  EXPECT_EQ(builder.rememberedIdentities(), 1u);
}

TEST(GraphBuilder, RefusesAFrameOutOfSequenceOrWithANonFiniteValue) {
  BackendParams params;
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  FrameMeasurement f;
  f.frame_index = 1;  // the graph is empty: frame 0 expected
  EXPECT_THROW(builder.addFrame(f), std::invalid_argument);
  f.frame_index = 0;
  f.static_points = {{1, Vec3(NAN, 0.0, 5.0)}};
  EXPECT_THROW(builder.addFrame(f), std::invalid_argument);
  EXPECT_EQ(graph.numFrames(), 0);  // nothing half-added
  f.static_points = {{1, Vec3(0.0, 0.0, 5.0)}};
  builder.addFrame(f);
  EXPECT_EQ(graph.numFrames(), 1);
}

TEST(GraphBuilder, OptionsLeaveOutWhatABaselineDoesNotUse) {
  FrameMeasurement f0, f1;
  f1.frame_index = 1;
  f1.odometry = OdometryMeasurement{SE3::Identity(), Vec6::Constant(0.01)};
  ObjectObservation o;
  o.object_id = 3;
  for (int i = 0; i < 6; ++i) o.points.push_back({50 + i, Vec3(0.3 * i, 0.1 * (i % 2), 8.0)});
  f0.static_points = f1.static_points = {{1, Vec3(0.0, 0.0, 5.0)}};
  f0.objects = f1.objects = {o};
  BackendParams params;
  BuilderOptions static_only;
  static_only.use_objects = false;
  FactorGraph graph;
  GraphBuilder builder(params, static_only, &graph);
  builder.addFrame(f0);
  builder.addFrame(f1);
  EXPECT_EQ(graph.points.size(), 1u);  // the landmark alone
  EXPECT_TRUE(graph.motions.empty());
  EXPECT_TRUE(graph.transitions.empty());
  BuilderOptions no_odometry;
  no_odometry.use_odometry = false;
  FactorGraph without;
  GraphBuilder builder2(params, no_odometry, &without);
  builder2.addFrame(f0);
  builder2.addFrame(f1);
  EXPECT_FALSE(without.frame(1).odometry.has_value());
  EXPECT_GT(without.points.size(), 1u);
}

TEST(GraphBuilder, StartsFromTheFrontEndsMotionFitAndChecksItsInliersInTheWorld) {
  const SE3 H(Eigen::AngleAxisd(0.05, Vec3::UnitY()).toRotationMatrix(), Vec3(0.2, 0.0, 0.8));
  FrameMeasurement f0, f1;
  f1.frame_index = 1;
  f1.odometry = OdometryMeasurement{SE3::Identity(), Vec6::Constant(0.01)};
  ObjectObservation a, b;
  a.object_id = b.object_id = 5;
  for (int i = 0; i < 12; ++i) {
    const Vec3 p(1.0 + 0.3 * (i % 4), 0.2 * (i / 4), 10.0 + 0.1 * i);
    a.points.push_back({100 + i, p});
    // Track 100 jumped to another surface: 1 m off.
    b.points.push_back({100 + i, H * p + (i == 0 ? Vec3(0.0, 1.0, 0.0) : Vec3::Zero())});
  }
  ObjectMotionFit fit;  // a little off, as a fit on the front-end's raw depths would be
  fit.H_camera_prev = H * SE3::Exp((Vec6() << 0.02, 0.0, 0.01, 0.0, 0.002, 0.0).finished());
  fit.num_inliers = 12;
  b.motion_fit = fit;
  f0.objects = {a};
  f1.objects = {b};
  BackendParams params;
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  builder.addFrame(f0);
  builder.addFrame(f1);
  // The jumped track gets no ternary factor; H starts from the refit on the others: the true motion.
  EXPECT_EQ(graph.frame(1).point_motions.size(), 11u);
  ASSERT_EQ(graph.motions.size(), 1u);
  EXPECT_TRUE(graph.motions.begin()->second.worldMotion().isApprox(H, 1e-9));
}

TEST(GraphBuilder, DepthNoiseWeighsEachPointAlongItsViewingRay) {
  // Stereo depth: sigma_z = sigma_0 + k z^2 along the ray, which moves x and y by x/z and y/z of it.
  BackendParams params;
  params.noise.point_sigma_m = 0.02;
  params.noise.point_sigma_per_depth_sq = 1e-3;
  FrameMeasurement f0;
  f0.static_points = {{1, Vec3(0.0, 0.0, 10.0)}, {2, Vec3(5.0, -2.0, 10.0)}, {3, Vec3(0.0, 0.0, 2.0)}};
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  builder.addFrame(f0);
  const auto& m = graph.frame(0).measurements;
  ASSERT_EQ(m.size(), 3u);
  EXPECT_TRUE(m[0].sigma_m.isApprox(Vec3(0.02, 0.02, 0.12), 1e-12));             // on the axis: depth only
  EXPECT_TRUE(m[1].sigma_m.isApprox(Vec3(0.02 + 0.05, 0.02 + 0.02, 0.12), 1e-12));  // x/z = 0.5, y/z = 0.2
  EXPECT_TRUE(m[2].sigma_m.isApprox(Vec3(0.02, 0.02, 0.024), 1e-12));            // near: barely more
  params.noise.point_sigma_per_depth_sq = 0.0;  // RGB-D default: every axis the same
  FactorGraph flat;
  GraphBuilder flat_builder(params, BuilderOptions{}, &flat);
  flat_builder.addFrame(f0);
  EXPECT_TRUE(flat.frame(0).measurements[1].sigma_m.isApprox(Vec3::Constant(0.02), 1e-12));
}

TEST(GraphBuilder, AJitteringStaticObjectsPointsWeighAsOneLandmarkOfItsJitter) {
  // 16 points of a static object whose position jitters by 3 cm: as static structure each point's
  // variance grows by 16 x (3 cm)^2, so together they tell the camera what one 3 cm landmark would.
  // Measured while dynamic, or static without jitter, the points keep the configured sigma.
  BackendParams params;
  params.noise.point_sigma_m = 0.02;
  auto frame = [](int k, bool dynamic, double jitter_m) {
    FrameMeasurement f;
    f.frame_index = k;
    if (k > 0) f.odometry = OdometryMeasurement{SE3::Identity(), Vec6::Constant(0.01)};
    ObjectObservation o;
    o.object_id = 5;
    o.is_dynamic = dynamic;
    o.jitter_sigma_m = jitter_m;
    for (int i = 0; i < 16; ++i) o.points.push_back({100 + i, Vec3(1.0 + 0.3 * (i % 4), 0.2 * (i / 4), 10.0)});
    f.objects = {o};
    return f;
  };
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  builder.addFrame(frame(0, true, 0.0));
  builder.addFrame(frame(1, false, 0.0));
  builder.addFrame(frame(2, false, 0.03));
  const double widened = std::sqrt(0.02 * 0.02 + 16 * 0.03 * 0.03);
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(graph.frame(k).measurements.size(), 16u) << k;
    for (const auto& m : graph.frame(k).measurements)
      EXPECT_TRUE(m.sigma_m.isApprox(Vec3::Constant(k == 2 ? widened : 0.02), 1e-12)) << k;
  }
  // A jitter that is not a finite non-negative sigma is bad input, refused with the object named.
  for (const double bad : {-0.01, static_cast<double>(NAN)}) {
    try {
      builder.addFrame(frame(3, false, bad));
      ADD_FAILURE() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("object 5 jitter"), std::string::npos) << e.what();
    }
  }
}

// After dropped frames (serve when it falls behind) a transition spans several frame periods: a motion model
// must not tie its motion to one over a single period, and its speed is per second of its own step. A car at
// 10 m/s seen at 0, 0.1, 0.2, 0.6, 0.7 and 0.8 s by a still camera.
std::vector<FrameMeasurement> CarWithAGap(bool stamped) {
  const double t_s[] = {0.0, 0.1, 0.2, 0.6, 0.7, 0.8};
  std::vector<FrameMeasurement> frames;
  for (int k = 0; k < 6; ++k) {
    FrameMeasurement f;
    f.frame_index = k;
    f.t_ns = stamped ? static_cast<int64_t>(std::llround(t_s[k] * 1e9)) : 0;
    if (k > 0) f.odometry = OdometryMeasurement{SE3::Identity(), Vec6::Constant(0.01)};
    ObjectObservation car;
    car.object_id = 3;
    for (int i = 0; i < 12; ++i)
      car.points.push_back({100 + i, Vec3(1.0 + 0.3 * (i % 4) + 10.0 * t_s[k], 0.2 * (i / 4), 10.0 + 0.1 * i)});
    f.objects = {car};
    frames.push_back(f);
  }
  return frames;
}

TEST(GraphBuilder, MotionModelsTieOnlyMotionsOfEqualStepsAndSpeedsAreOverTheStep) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  for (const FrameMeasurement& f : CarWithAGap(true)) builder.addFrame(f);
  // 0.1 s steps into frames 1, 2, 4, 5; 0.4 s into frame 3: no smoothness factor into or out of it.
  const size_t expected_smoothness[] = {0, 0, 1, 0, 0, 1};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(graph.frame(k).smoothness.size(), expected_smoothness[k]) << k;
  int motions = 0;
  for (const ObjectTransition& tr : graph.transitions) {
    if (tr.motion_var < 0) continue;  // the first sighting: no motion
    ++motions;
    EXPECT_NEAR(tr.step_s, tr.frame == 3 ? 0.4 : 0.1, 1e-9) << tr.frame;
    const ObjectMotionEstimate m = MotionEstimateOf(graph, tr, 10.0);  // 10 Hz nominal
    EXPECT_NEAR(m.step_s, tr.step_s, 1e-12);
    EXPECT_NEAR(m.speed_mps, 10.0, 1e-6) << tr.frame;  // not 40 over the gap
    EXPECT_TRUE(m.velocityMps(10.0).isApprox(Vec3(10.0, 0.0, 0.0), 1e-6)) << tr.frame;
  }
  EXPECT_EQ(motions, 5);

  // Constant mode: one motion per run of equal steps (frames 1-2, 3, 4-5).
  params.default_mode = MotionMode::kConstant;
  FactorGraph constant;
  GraphBuilder constant_builder(params, BuilderOptions{}, &constant);
  for (const FrameMeasurement& f : CarWithAGap(true)) constant_builder.addFrame(f);
  EXPECT_EQ(constant.motions.size(), 3u);

  // Frames without stamps: every step is the nominal one, and the model ties them all, as before.
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph unstamped;
  GraphBuilder unstamped_builder(params, BuilderOptions{}, &unstamped);
  for (const FrameMeasurement& f : CarWithAGap(false)) unstamped_builder.addFrame(f);
  for (int k = 2; k < 6; ++k) EXPECT_EQ(unstamped.frame(k).smoothness.size(), 1u) << k;
  for (const ObjectTransition& tr : unstamped.transitions) {
    EXPECT_EQ(tr.step_s, 0.0);
    if (tr.motion_var >= 0) EXPECT_NEAR(MotionEstimateOf(unstamped, tr, 10.0).speed_mps, tr.frame == 3 ? 40.0 : 10.0, 1e-6);
  }
}

}  // namespace
}  // namespace dslam
