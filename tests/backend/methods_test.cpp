#include "backend/methods.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

TEST(Methods, BaselinesAreBuiltFromTheSameParts) {
  ScenarioOptions opt;
  opt.num_frames = 40;
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> frames = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &frames);
  BackendParams params;
  const MethodResult static_only = RunMethod(Method::kStaticOnly, params, seq.frame_rate_hz, frames);
  const MethodResult slam_mot = RunMethod(Method::kSlamMot, params, seq.frame_rate_hz, frames);
  const MethodResult ours = RunMethod(Method::kOurs, params, seq.frame_rate_hz, frames);

  EXPECT_TRUE(static_only.estimate.object_motions.empty());
  for (const auto& p : static_only.estimate.points) EXPECT_EQ(p.object_id, -1);
  // SLAM+MOT keeps the static stage's cameras exactly and adds object motions.
  ASSERT_EQ(slam_mot.estimate.T_world_camera.size(), static_only.estimate.T_world_camera.size());
  for (size_t k = 0; k < frames.size(); ++k)
    EXPECT_EQ(slam_mot.estimate.T_world_camera[k].matrix(), static_only.estimate.T_world_camera[k].matrix());
  EXPECT_FALSE(slam_mot.estimate.object_motions.empty());
  EXPECT_FALSE(ours.estimate.object_motions.empty());
  // Ours moves the cameras off the static-only solution (the objects inform them).
  double diff = 0.0;
  for (size_t k = 0; k < frames.size(); ++k)
    diff += (ours.estimate.T_world_camera[k].translation() - static_only.estimate.T_world_camera[k].translation()).norm();
  EXPECT_GT(diff, 1e-6);
  EXPECT_EQ(ToString(Method::kSlamMot), "slam_mot");
}

TEST(Methods, ObjectsInformTheCameraOnlyThroughTheirMotionModelAndTheStaticMap) {
  // Each frame's object points are new variables tied by a free per-frame motion: whatever the camera
  // does, H absorbs it. So without a motion model (per-step) and with no object merged into the static
  // map, ours' cameras are static-only's. What moves them is the motion model (smoothed here) or a
  // static object's points, the two places to look when the objects pull the camera.
  ScenarioOptions opt;
  opt.num_frames = 40;
  opt.noise.point_sigma_m = 0.04;
  const Sequence seq = MakeScenario("city", opt);
  ClassifierParams never_static;
  never_static.min_static_transitions = 1000000;
  std::vector<FrameMeasurement> frames = seq.frames;
  LabelDynamicObjects(never_static, seq.frame_rate_hz, &frames);
  BackendParams params;
  params.batch_function_tolerance = 1e-12;  // both solved to the end: what remains is the model's doing
  params.max_iterations_batch = 200;
  params.noise.point_sigma_m = 0.04;
  const MethodResult static_only = RunMethod(Method::kStaticOnly, params, seq.frame_rate_hz, frames);
  auto largest_difference_m = [&](MotionMode mode) {
    params.default_mode = mode;
    const MethodResult ours = RunMethod(Method::kOurs, params, seq.frame_rate_hz, frames);
    EXPECT_FALSE(ours.estimate.object_motions.empty());
    double largest = 0.0;
    for (size_t k = 0; k < frames.size(); ++k)
      largest = std::max(largest, (ours.estimate.T_world_camera[k].translation() -
                                   static_only.estimate.T_world_camera[k].translation()).norm());
    return largest;
  };
  EXPECT_LT(largest_difference_m(MotionMode::kPerStep), 1e-5);
  EXPECT_GT(largest_difference_m(MotionMode::kSmoothed), 1e-3);
}

}  // namespace
}  // namespace dslam
