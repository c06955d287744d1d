#include "backend/methods.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace dslam
