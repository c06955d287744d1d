#include "backend/estimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "backend/factors/pose_block.h"
#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

struct NullSink : EstimateSink {
  void cameraFinal(int frame, const SE3&) override { EXPECT_EQ(frame, cameras++); }
  void motionFinal(const ObjectMotionEstimate&) override {}
  void pointFinal(const PointEstimate&) override {}
  int cameras = 0;
};

std::vector<FrameMeasurement> Labelled(const Sequence& seq) {
  std::vector<FrameMeasurement> frames = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &frames);
  return frames;
}

double MeanStepTranslationError(const std::vector<SE3>& gt, const std::vector<SE3>& est) {
  double sum = 0.0;
  for (size_t k = 1; k < gt.size(); ++k)
    sum += ((gt[k - 1].inverse() * gt[k]).inverse() * (est[k - 1].inverse() * est[k])).translation().norm();
  return sum / static_cast<double>(gt.size() - 1);
}

TEST(Estimator, JointEstimateBeatsOdometryOnThePaperScene) {
  ScenarioOptions opt;
  opt.num_frames = 30;
  const Sequence seq = MakeScenario("paper", opt);
  BackendParams params;
  params.default_mode = MotionMode::kConstant;
  Estimator estimator(params, seq.frame_rate_hz);
  std::vector<SE3> odometry_only = {SE3::Identity()};
  for (const auto& f : Labelled(seq)) {
    estimator.addFrame(f);
    if (f.odometry) odometry_only.push_back(odometry_only.back() * f.odometry->T_prev_curr);
  }
  const Estimate est = estimator.finish();
  ASSERT_EQ(est.T_world_camera.size(), seq.frames.size());
  EXPECT_LT(MeanStepTranslationError(seq.gt.T_world_camera, est.T_world_camera),
            0.6 * MeanStepTranslationError(seq.gt.T_world_camera, odometry_only));
  // One constant H for the object: every transition reports the same motion.
  ASSERT_EQ(est.object_motions.size(), seq.frames.size() - 1);
  for (const auto& m : est.object_motions) EXPECT_TRUE(m.H_world.isApprox(est.object_motions.front().H_world, 1e-12));
  const SE3& L0 = seq.gt.objects.at(1).L_world_object.at(0);
  const SE3 H_gt = seq.gt.objects.at(1).L_world_object.at(1) * L0.inverse();
  const SE3 error = (L0.inverse() * H_gt * L0).inverse() * (L0.inverse() * est.object_motions.front().H_world * L0);
  EXPECT_LT(error.translation().norm(), 0.05);
}

TEST(Estimator, SchurAndCholeskyReachTheSameSolution) {
  ScenarioOptions opt;
  opt.num_frames = 40;
  const Sequence seq = MakeScenario("city", opt);
  const auto frames = Labelled(seq);
  std::vector<Estimate> results;
  for (LinearSolver solver : {LinearSolver::kCholesky, LinearSolver::kSchur}) {
    BackendParams params;
    params.linear_solver = solver;
    params.default_mode = MotionMode::kSmoothed;
    Estimator estimator(params, seq.frame_rate_hz);
    for (const auto& f : frames) estimator.addFrame(f);
    results.push_back(estimator.finish());
  }
  for (size_t k = 0; k < frames.size(); ++k)
    EXPECT_TRUE(results[0].T_world_camera[k].isApprox(results[1].T_world_camera[k], 1e-5)) << k;
  ASSERT_EQ(results[0].object_motions.size(), results[1].object_motions.size());
  for (size_t i = 0; i < results[0].object_motions.size(); ++i)
    EXPECT_TRUE(results[0].object_motions[i].H_world.isApprox(results[1].object_motions[i].H_world, 1e-5)) << i;
}

TEST(Estimator, RejectsFramesOutOfSequence) {
  Estimator estimator(BackendParams{}, 10.0);
  FrameMeasurement f;
  f.frame_index = 3;
  EXPECT_THROW(estimator.addFrame(f), std::invalid_argument);
  f.frame_index = 0;
  f.static_points.push_back({1, Vec3(NAN, 0.0, 5.0)});
  EXPECT_THROW(estimator.addFrame(f), std::invalid_argument);
}

TEST(Estimator, InvalidParametersAreRejectedAtConstruction) {
  BackendParams p;
  p.noise.motion_sigma_m = 0.0;
  EXPECT_THROW(Estimator(p, 10.0), std::invalid_argument);
  EXPECT_THROW(Estimator(BackendParams{}, 0.0), std::invalid_argument);
}

TEST(Estimator, StaticTransitionsShareVariablesAndDynamicOnesChainThem) {
  ScenarioOptions opt;
  opt.num_frames = 120;
  const Sequence seq = MakeScenario("city", opt);
  Estimator estimator(BackendParams{}, seq.frame_rate_hz);
  for (const auto& f : Labelled(seq)) estimator.addFrame(f);
  const FactorGraph& g = estimator.graph();
  int static_transitions = 0, dynamic_transitions = 0;
  for (const auto& tr : g.transitions) (tr.is_dynamic ? dynamic_transitions : static_transitions)++;
  EXPECT_GT(static_transitions, 0);  // parked cars
  EXPECT_GT(dynamic_transitions, 0);
  // Schur elimination group: no factor may link two points of the first group.
  for (const auto& frame : g.frames)
    for (const auto& m : frame.point_motions)
      EXPECT_FALSE(g.points.at(m.prev_point_var).eliminate_first && g.points.at(m.curr_point_var).eliminate_first);
}

TEST(FixedLagSmoother, ProblemSizeAndStoredGraphDoNotGrowWithSequenceLength) {
  ScenarioOptions opt;
  opt.num_frames = 100 + kCityCycleFrames + 1;
  const Sequence seq = MakeScenario("city", opt);
  BackendParams params;
  params.schedule = {ScheduleKind::kSlidingWindow, 10};
  NullSink discard;
  EstimatorOptions options;
  options.sink = &discard;
  Estimator estimator(params, seq.frame_rate_hz, options);
  const auto frames = Labelled(seq);
  struct Size {
    int residual_blocks, points, motions, frames;
    size_t identities;
  };
  std::vector<Size> sizes;
  for (size_t k = 0; k < frames.size(); ++k) {
    estimator.addFrame(frames[k]);
    if (k == 100 || k == 100 + kCityCycleFrames) {
      const FactorGraph& g = estimator.graph();
      sizes.push_back({estimator.solveResidualBlocks().back(), static_cast<int>(g.points.size()),
                       static_cast<int>(g.motions.size()), static_cast<int>(g.frames.size()),
                       estimator.builder().rememberedIdentities()});
    }
  }
  ASSERT_EQ(sizes.size(), 2u);
  EXPECT_GT(sizes[0].residual_blocks, 0);
  // The city repeats every cycle: frame 100 of the second cycle has the same window, and a
  // sequence-length-dependent cost or storage would show here.
  EXPECT_LT(std::abs(sizes[1].residual_blocks - sizes[0].residual_blocks), 0.02 * sizes[0].residual_blocks);
  EXPECT_LT(std::abs(sizes[1].points - sizes[0].points), 0.02 * sizes[0].points);
  EXPECT_EQ(sizes[1].motions, sizes[0].motions);
  EXPECT_EQ(sizes[0].frames, 11);  // the window and its anchor camera
  EXPECT_EQ(sizes[1].frames, 11);
  // The builder forgets tracks whose variables were retired: what it remembers stays bounded.
  // (Without forgetting: 301 at frame 100, 922 at frame 400.)
  EXPECT_LT(sizes[1].identities, 1.5 * sizes[0].identities);
  EXPECT_EQ(discard.cameras, static_cast<int>(frames.size()) - 10);
}


TEST(FixedLagSmoother, ObjectsWithOneMotionKeepTheirPointsForTheCameraWindow) {
  ScenarioOptions opt;
  opt.num_frames = 30;
  const Sequence seq = MakeScenario("city", opt);
  const auto frames = Labelled(seq);
  // The object seen dynamic most often gets one motion for its whole track; the others one per frame.
  std::map<int, int> dynamic_frames;
  for (const auto& f : frames)
    for (const auto& o : f.objects) dynamic_frames[o.object_id] += o.is_dynamic;
  ASSERT_FALSE(dynamic_frames.empty());
  const int constant_object =
      std::max_element(dynamic_frames.begin(), dynamic_frames.end(), [](auto& a, auto& b) { return a.second < b.second; })
          ->first;
  ASSERT_GT(dynamic_frames[constant_object], 20);
  BackendParams params;
  params.schedule = {ScheduleKind::kSlidingWindow, 8};
  params.object_window_frames = 3;
  params.mode_per_object[constant_object] = MotionMode::kConstant;
  struct MotionRecorder : NullSink {
    void motionFinal(const ObjectMotionEstimate& m) override { motions.push_back(m); }
    std::vector<ObjectMotionEstimate> motions;
  } discard;
  EstimatorOptions options;
  options.sink = &discard;
  Estimator estimator(params, seq.frame_rate_hz, options);
  int checked = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    estimator.addFrame(frames[k]);
    if (k < 12) continue;
    int oldest_constant = static_cast<int>(k), oldest_per_frame = static_cast<int>(k);
    for (const auto& [id, var] : estimator.graph().points) {
      if (var.object_id < 0 || var.first_frame != var.last_frame) continue;
      int& oldest = var.object_id == constant_object ? oldest_constant : oldest_per_frame;
      oldest = std::min(oldest, var.first_frame);
    }
    EXPECT_EQ(oldest_per_frame, static_cast<int>(k) - 2) << k;
    if (oldest_constant < static_cast<int>(k)) {
      EXPECT_EQ(oldest_constant, static_cast<int>(k) - 7) << k;
      ++checked;
    }
    // Every transition still in the graph refers to live variables (the solver ran on it).
    for (const auto& tr : estimator.graph().transitions) {
      if (tr.motion_var < 0) continue;
      EXPECT_TRUE(estimator.graph().motions.count(tr.motion_var)) << k;
    }
  }
  EXPECT_GT(checked, 5);
  estimator.finish();
  // The one motion keeps being refined while the track goes on: its transitions are final together, when
  // it leaves, all with its final value.
  std::vector<SE3> constant_H;
  for (const auto& m : discard.motions)
    if (m.object_id == constant_object && m.is_dynamic) constant_H.push_back(m.H_world);
  ASSERT_GT(constant_H.size(), 10u);
  for (const SE3& H : constant_H) EXPECT_TRUE(H.isApprox(constant_H.front(), 0.0));
  EXPECT_EQ(discard.cameras, static_cast<int>(frames.size()));
}

// Records the order of what a sink receives, and each step covariance.
struct StepRecorder : EstimateSink {
  void cameraFinal(int frame, const SE3&) override { events.push_back("camera " + std::to_string(frame)); }
  void motionFinal(const ObjectMotionEstimate&) override {}
  void pointFinal(const PointEstimate&) override {}
  void cameraStepCovariance(int frame, const Mat6& covariance) override {
    events.push_back("step " + std::to_string(frame));
    steps[frame] = covariance;
  }
  std::vector<std::string> events;
  std::map<int, Mat6> steps;
};

// Odometry alone: each step's covariance is its odometry's (pure translation steps, so the odometry's
// tangent and the step's agree), whatever the schedule, handed over just before its camera.
TEST(Estimator, EachCameraStepComesWithItsCovarianceJustBeforeItsCamera) {
  Vec6 sigma;
  sigma << 0.01, 0.02, 0.03, 0.001, 0.002, 0.003;
  std::vector<FrameMeasurement> frames(9);
  for (int k = 0; k < 9; ++k) {
    frames[k].frame_index = k;
    frames[k].t_ns = k * 100'000'000LL;
    if (k > 0) frames[k].odometry = OdometryMeasurement{SE3(Eigen::Quaterniond::Identity(), Vec3(0.1, 0.0, 1.0)), sigma};
  }
  for (const std::string schedule : {"batch", "window:4"}) {
    BackendParams params;
    params.schedule = ParseSchedule(schedule);
    StepRecorder recorder;
    EstimatorOptions options;
    options.sink = &recorder;
    Estimator estimator(params, 10.0, options);
    for (const auto& f : frames) estimator.addFrame(f);
    estimator.finish();
    ASSERT_EQ(recorder.events.size(), 17u) << schedule;  // 9 cameras, 8 steps
    EXPECT_EQ(recorder.events[0], "camera 0") << schedule;
    for (int k = 1; k < 9; ++k) {
      EXPECT_EQ(recorder.events[2 * k - 1], "step " + std::to_string(k)) << schedule;
      EXPECT_EQ(recorder.events[2 * k], "camera " + std::to_string(k)) << schedule;
      const Mat6 odometry = sigma.array().square().matrix().asDiagonal();
      EXPECT_LT((recorder.steps.at(k) - odometry).norm(), 1e-6 * odometry.norm()) << schedule << " step " << k << "\n" << recorder.steps.at(k);
    }
  }
}

}  // namespace
}  // namespace dslam
