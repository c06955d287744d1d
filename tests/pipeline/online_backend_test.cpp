// The back-end as a stage of the online pipeline: a frame it refuses leaves no trace, so that the stage
// before it can take its own step back and both commit a frame together or not at all.
#include "pipeline/online_backend.h"

#include <gtest/gtest.h>

#include <cmath>

#include "simulation/scenarios.h"

namespace dslam {
namespace {

TEST(OnlineBackend, ARefusedFrameChangesNothingAndTheNextFramesEstimatesAreAsIfItNeverCame) {
  ScenarioOptions opt;
  opt.num_frames = 14;
  const Sequence seq = MakeScenario("city", opt);
  RunConfig config;
  config.backend.default_mode = MotionMode::kSmoothed;
  config.backend.schedule = {ScheduleKind::kSlidingWindow, 6};
  OnlineBackend reference(config, seq.frame_rate_hz);
  OnlineBackend refusing(config, seq.frame_rate_hz);
  constexpr int kBad = 7;
  for (int k = 0; k < static_cast<int>(seq.frames.size()); ++k) {
    if (k == kBad) {
      // The same frame with one object point not finite: the estimator's check refuses it, before the
      // classifier labelled it and before anything was written.
      FrameMeasurement bad = seq.frames[k];
      ASSERT_FALSE(bad.objects.empty());
      ASSERT_FALSE(bad.objects[0].points.empty());
      bad.objects[0].points[0].p_camera.x() = std::nan("");
      try {
        refusing.add(&bad);
        FAIL() << "accepted a non-finite point";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("is not finite"), std::string::npos) << e.what();
      }
      FrameMeasurement wrong_area = seq.frames[k];  // a mask over more than the whole image
      wrong_area.objects[0].mask_area_frac = 1.5;
      try {
        refusing.add(&wrong_area);
        FAIL() << "accepted a mask area share of 1.5";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("mask area share must be in [0, 1]"), std::string::npos) << e.what();
      }
      FrameMeasurement skipped = seq.frames[k];
      skipped.frame_index = k + 1;  // out of sequence
      EXPECT_THROW(refusing.add(&skipped), std::invalid_argument);
      EXPECT_EQ(refusing.framesAdded(), kBad);
    }
    FrameMeasurement a = seq.frames[k], b = seq.frames[k];
    const FrameEstimate ea = reference.add(&a);
    const FrameEstimate eb = refusing.add(&b);
    EXPECT_EQ((ea.T_world_camera.translation() - eb.T_world_camera.translation()).norm(), 0.0) << k;
    ASSERT_EQ(ea.object_motions.size(), eb.object_motions.size()) << k;
    for (size_t i = 0; i < ea.object_motions.size(); ++i) {
      EXPECT_EQ(ea.object_motions[i].speed_mps, eb.object_motions[i].speed_mps) << k;
      EXPECT_EQ(ea.object_motions[i].is_dynamic, eb.object_motions[i].is_dynamic) << k;
    }
  }
  EXPECT_EQ(refusing.framesAdded(), static_cast<int>(seq.frames.size()));
}

}  // namespace
}  // namespace dslam
