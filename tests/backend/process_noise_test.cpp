#include "backend/process_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <vector>

#include "backend/estimator.h"
#include "backend/factors/pose_block.h"
#include "support/city_graph.h"

namespace dslam {
namespace {

constexpr int kWeaver = 7, kSteady = 8;

BackendParams FromResiduals() {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  params.noise.smoothness_from_residuals = true;
  return params;
}

// Frames 0..frames-1; each object has a motion per frame 1.. and a smoothness factor per frame 2..: the
// weaver's motion swings 0.4 m sideways every frame (x = +-0.2 m), the steady one repeats one motion.
FactorGraph TwoObjectGraph(int frames) {
  FactorGraph graph;
  for (int k = 0; k < frames; ++k) {
    graph.frames.emplace_back();
    graph.camera_poses.emplace_back();
    PoseToBlock(SE3::Identity(), graph.camera_poses.back().data());
  }
  std::vector<int> last_motion = {-1, -1};
  for (int k = 1; k < frames; ++k) {
    for (int j = 0; j < 2; ++j) {
      MotionVariable m;
      m.object_id = j == 0 ? kWeaver : kSteady;
      m.first_frame = m.last_frame = k;
      const double x = j == 0 ? (k % 2 == 0 ? 0.2 : -0.2) : 0.1;
      PoseToBlock(SE3(Mat3::Identity(), Vec3(x, 0.0, 1.0)), m.H_anchor.data());
      const int id = graph.next_motion_id++;
      graph.motions[id] = m;
      if (last_motion[j] >= 0) graph.frame(k).smoothness.push_back({last_motion[j], id, {}, Vec3::Zero()});
      last_motion[j] = id;
    }
  }
  return graph;
}

TEST(ProcessNoise, AnObjectThatChangesMoreThanConfiguredGetsItsTranslationSigmaScaledByItsResiduals) {
  const BackendParams params = FromResiduals();
  FactorGraph graph = TwoObjectGraph(6);
  EXPECT_GT(UpdateSmoothnessScales(params, 0, 5, &graph), 1.0);
  // Each of the weaver's 4 factors: 0.4 m / 0.1 m = 4 on one axis, so 16 / 3 per translation dimension.
  EXPECT_NEAR(graph.smoothness_noise.at(kWeaver).scale_t, std::sqrt(16.0 / 3.0), 1e-9);
  EXPECT_DOUBLE_EQ(graph.smoothness_noise.at(kWeaver).scale_r, 1.0);
  EXPECT_DOUBLE_EQ(graph.smoothness_noise.at(kSteady).scale_t, 1.0);  // never tighter than configured
  EXPECT_DOUBLE_EQ(graph.smoothness_noise.at(kSteady).scale_r, 1.0);
  const Vec6 sigma = SmoothnessSigma(params, graph, kWeaver);
  EXPECT_NEAR(sigma(0), params.noise.smoothness_sigma_t_m * std::sqrt(16.0 / 3.0), 1e-12);
  EXPECT_DOUBLE_EQ(sigma(3), params.noise.smoothness_sigma_r_rad);
  EXPECT_DOUBLE_EQ(UpdateSmoothnessScales(params, 0, 5, &graph), 0.0);  // the same values: settled
}

TEST(ProcessNoise, FewerFactorsThanTheMinimumOrTheOptionOffKeepTheConfiguredSigmas) {
  FactorGraph short_track = TwoObjectGraph(kMinSmoothnessFactorsForScale + 1);  // one factor too few
  UpdateSmoothnessScales(FromResiduals(), 0, kMinSmoothnessFactorsForScale, &short_track);
  EXPECT_TRUE(short_track.smoothness_noise.empty() || short_track.smoothness_noise.at(kWeaver).scale_t == 1.0);

  BackendParams off = FromResiduals();
  off.noise.smoothness_from_residuals = false;
  FactorGraph graph = TwoObjectGraph(6);
  EXPECT_EQ(UpdateSmoothnessScales(off, 0, 5, &graph), 0.0);
  AccumulateLeavingSmoothness(off, 3, &graph);
  EXPECT_TRUE(graph.smoothness_noise.empty());
  EXPECT_TRUE(SmoothnessSigma(off, graph, kWeaver).isApprox(SmoothnessSigma(off, TwoObjectGraph(2), kWeaver), 0.0));
}

// The smoother's path: residuals of factors that left the window count with those still in it.
TEST(ProcessNoise, ResidualsOfFactorsThatLeftTheWindowKeepCounting) {
  const BackendParams params = FromResiduals();
  FactorGraph all_in_window = TwoObjectGraph(6);
  UpdateSmoothnessScales(params, 0, 5, &all_in_window);

  FactorGraph smoother = TwoObjectGraph(6);
  for (int k = 0; k <= 3; ++k) {  // frames 0..3 leave: their smoothness factors become final statistics
    AccumulateLeavingSmoothness(params, k, &smoother);
    smoother.frame(k).smoothness.clear();
  }
  EXPECT_EQ(smoother.smoothness_noise.at(kWeaver).final.count, 2);  // frames 2 and 3
  UpdateSmoothnessScales(params, 4, 5, &smoother);
  EXPECT_NEAR(smoother.smoothness_noise.at(kWeaver).scale_t, all_in_window.smoothness_noise.at(kWeaver).scale_t, 1e-12);
}

TEST(ProcessNoise, AnObjectWithNoMotionLeftIsForgottenAndTheOthersKept) {
  FactorGraph graph = TwoObjectGraph(6);
  UpdateSmoothnessScales(FromResiduals(), 0, 5, &graph);
  ASSERT_EQ(graph.smoothness_noise.size(), 2u);
  for (int k = 0; k < 6; ++k) graph.frame(k).smoothness.clear();
  for (auto it = graph.motions.begin(); it != graph.motions.end();)
    it = it->second.object_id == kWeaver ? graph.motions.erase(it) : std::next(it);
  ForgetObjectsWithoutMotions(&graph);
  EXPECT_FALSE(graph.smoothness_noise.count(kWeaver));
  EXPECT_TRUE(graph.smoothness_noise.count(kSteady));
}

// The city's largest moving object weaves +-0.3 m sideways frame to frame: how far that moves the final
// cameras, with the configured smoothness sigmas and with the object's own process noise.
double CameraPullOfAWeave(const BackendParams& params) {
  constexpr int kFrames = 12;
  const std::vector<FrameMeasurement> clean = test::LabelledCityFrames(kFrames);
  std::vector<FrameMeasurement> weaving = clean;
  int weaver = -1;
  size_t most_points = 0;
  for (const ObjectObservation& o : clean[1].objects)
    if (o.is_dynamic && o.reported == ReportedMotion::kMoving && o.points.size() > most_points) {
      weaver = o.object_id;
      most_points = o.points.size();
    }
  EXPECT_GE(weaver, 0);
  for (int k = 0; k < kFrames; ++k)
    for (ObjectObservation& o : weaving[k].objects)
      if (o.object_id == weaver)
        for (PointObservation& p : o.points) p.p_camera += Vec3(k % 2 == 0 ? 0.3 : -0.3, 0.0, 0.0);
  const auto cameras = [&](const std::vector<FrameMeasurement>& frames) {
    Estimator estimator(params, 10.0);
    for (const FrameMeasurement& f : frames) estimator.addFrame(f);
    return estimator.finish().T_world_camera;
  };
  const std::vector<SE3> before = cameras(clean), after = cameras(weaving);
  double pull_m = 0.0;
  for (int k = 0; k < kFrames; ++k) pull_m = std::max(pull_m, (before[k].translation() - after[k].translation()).norm());
  return pull_m;
}

TEST(ProcessNoise, AWeavingObjectPullsTheCamerasLessWithItsOwnProcessNoiseInBatchAndWindow) {
  for (const Schedule schedule : {Schedule{ScheduleKind::kBatch, 10}, Schedule{ScheduleKind::kSlidingWindow, 6}}) {
    BackendParams configured = FromResiduals();
    configured.noise.smoothness_from_residuals = false;
    configured.schedule = schedule;
    BackendParams own = configured;
    own.noise.smoothness_from_residuals = true;
    const double configured_m = CameraPullOfAWeave(configured), own_m = CameraPullOfAWeave(own);
    std::cout << (schedule.kind == ScheduleKind::kBatch ? "batch" : "window:6")
              << ": camera pull of a +-0.3 m weave: configured sigmas " << configured_m << " m, own process noise "
              << own_m << " m" << std::endl;
    EXPECT_GT(configured_m, 1e-4);  // the weave does reach the cameras through the configured smoothness
    EXPECT_LT(own_m, 0.5 * configured_m);
  }
}

}  // namespace
}  // namespace dslam
