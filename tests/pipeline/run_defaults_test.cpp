#include "pipeline/run_defaults.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(RunDefaults, ImageRunsAndTheServiceUseTheWindowAndTheOfflineRunsBatch) {
  for (EntryPoint online : {EntryPoint::kRun, EntryPoint::kStudy, EntryPoint::kServe}) {
    const RunConfig c = DefaultRunConfig(online);
    EXPECT_EQ(c.backend.default_mode, MotionMode::kSmoothed);
    EXPECT_EQ(ToString(c.backend.schedule), "window:10");
  }
  EXPECT_EQ(ToString(DefaultsOf(EntryPoint::kKittiReplay).schedule), "batch");
  EXPECT_EQ(DefaultsOf(EntryPoint::kKittiReplay).mode, MotionMode::kSmoothed);
  // sim follows its scenario's motion model.
  EXPECT_EQ(DefaultsOf(EntryPoint::kSim, "paper").mode, MotionMode::kConstant);
  EXPECT_EQ(DefaultsOf(EntryPoint::kSim, "city").mode, MotionMode::kSmoothed);
  EXPECT_EQ(ToString(DefaultRunConfig(EntryPoint::kSim, "city").backend.schedule), "batch");
  // Everything else is the built-in configuration's.
  const RunConfig built_in;
  EXPECT_EQ(DefaultRunConfig(EntryPoint::kRun).backend.noise.point_sigma_m, built_in.backend.noise.point_sigma_m);
  EXPECT_EQ(DefaultRunConfig(EntryPoint::kRun).frontend.object_max_distance_m, built_in.frontend.object_max_distance_m);
}

}  // namespace
}  // namespace dslam
