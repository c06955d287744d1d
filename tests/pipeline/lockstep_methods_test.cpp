#include "pipeline/lockstep_methods.h"

#include <gtest/gtest.h>

#include "simulation/scenarios.h"

namespace dslam {
namespace {

// The three methods side by side on one stream give what each gives alone on the whole labelled sequence.
TEST(LockstepMethods, EachMethodEstimatesWhatItEstimatesAlone) {
  ScenarioOptions opt;
  opt.num_frames = 25;
  const Sequence seq = MakeScenario("city", opt);
  RunConfig config;
  config.backend.schedule = {ScheduleKind::kSlidingWindow, 8};
  std::map<Method, CollectingSink> collected;
  std::map<Method, EstimateSink*> sinks;
  for (Method m : {Method::kOurs, Method::kStaticOnly, Method::kSlamMot}) sinks[m] = &collected[m];
  LockstepMethods methods(config, seq.frame_rate_hz, sinks);
  for (const FrameMeasurement& f : seq.frames) {
    const std::optional<FrameEstimate> latest = methods.add(f);
    ASSERT_TRUE(latest.has_value());
    EXPECT_EQ(latest->frame, f.frame_index);
    EXPECT_EQ(latest->t_ns, f.t_ns);
  }
  methods.finish();

  std::vector<FrameMeasurement> labelled = seq.frames;
  LabelDynamicObjects(config.classifier, seq.frame_rate_hz, &labelled);
  for (Method m : {Method::kOurs, Method::kStaticOnly, Method::kSlamMot}) {
    const Estimate alone = RunMethod(m, config.backend, seq.frame_rate_hz, labelled).estimate;
    const Estimate& stream = collected[m].estimate;
    ASSERT_EQ(stream.T_world_camera.size(), seq.frames.size()) << ToString(m);
    ASSERT_EQ(alone.T_world_camera.size(), seq.frames.size()) << ToString(m);
    for (size_t k = 0; k < seq.frames.size(); ++k)
      EXPECT_TRUE(stream.T_world_camera[k].isApprox(alone.T_world_camera[k], 1e-9)) << ToString(m) << " frame " << k;
    ASSERT_EQ(stream.object_motions.size(), alone.object_motions.size()) << ToString(m);
    for (size_t i = 0; i < stream.object_motions.size(); ++i) {
      EXPECT_EQ(stream.object_motions[i].object_id, alone.object_motions[i].object_id);
      EXPECT_NEAR(stream.object_motions[i].speed_mps, alone.object_motions[i].speed_mps, 1e-9) << ToString(m);
    }
    EXPECT_EQ(stream.points.size(), alone.points.size()) << ToString(m);
    EXPECT_GT(methods.wallTimeS(m), 0.0) << ToString(m);
  }
  EXPECT_TRUE(collected[Method::kStaticOnly].estimate.object_motions.empty());
  EXPECT_FALSE(collected[Method::kSlamMot].estimate.object_motions.empty());
}

// Only the methods given a sink run; without ours, each frame's estimate is the static stage's.
TEST(LockstepMethods, RunsOnlyTheMethodsThatHaveASink) {
  ScenarioOptions opt;
  opt.num_frames = 4;
  const Sequence seq = MakeScenario("city", opt);
  RunConfig config;
  config.backend.schedule = {ScheduleKind::kSlidingWindow, 8};
  CollectingSink static_only;
  LockstepMethods methods(config, seq.frame_rate_hz, {{Method::kStaticOnly, &static_only}});
  for (const FrameMeasurement& f : seq.frames) {
    const std::optional<FrameEstimate> latest = methods.add(f);
    ASSERT_TRUE(latest.has_value());
    EXPECT_EQ(latest->frame, f.frame_index);
    EXPECT_EQ(latest->t_ns, f.t_ns);
  }
  methods.finish();
  EXPECT_EQ(static_only.estimate.T_world_camera.size(), 4u);
  EXPECT_EQ(methods.wallTimeS(Method::kOurs), 0.0);
  // SLAM+MOT's time counts the static stage it shares with static-only; no object stage ran.
  EXPECT_EQ(methods.wallTimeS(Method::kSlamMot), methods.wallTimeS(Method::kStaticOnly));
}

TEST(LockstepMethods, RefusesToRunNoMethod) {
  RunConfig config;
  EXPECT_THROW(LockstepMethods(config, 10.0, {}), std::invalid_argument);
  EXPECT_THROW(LockstepMethods(config, 10.0, {{Method::kOurs, nullptr}}), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
