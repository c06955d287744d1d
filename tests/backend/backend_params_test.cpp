#include "backend/backend_params.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace dslam {
namespace {

TEST(BackendParams, DefaultsAreValid) { EXPECT_NO_THROW(BackendParams().validate()); }

TEST(BackendParams, NegativeSigmaIsAClearError) {
  BackendParams p;
  p.noise.point_sigma_m = -0.02;
  try {
    p.validate();
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point_sigma_m"), std::string::npos) << e.what();
  }
}

TEST(BackendParams, TheSmoothnessKernelIsOffAtZeroAndRefusedNegative) {
  BackendParams p;
  p.noise.smoothness_huber_delta = 0.0;
  EXPECT_NO_THROW(p.validate());
  for (const double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    p.noise.smoothness_huber_delta = bad;
    try {
      p.validate();
      ADD_FAILURE() << "expected an error for " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("smoothness_huber_delta"), std::string::npos) << e.what();
    }
  }
}

TEST(BackendParams, WindowMustHoldTwoFrames) {
  BackendParams p;
  p.schedule = {ScheduleKind::kSlidingWindow, 1};
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

TEST(BackendParams, PerObjectModeOverridesDefault) {
  BackendParams p;
  p.default_mode = MotionMode::kPerStep;
  p.mode_per_object[7] = MotionMode::kConstant;
  EXPECT_EQ(p.modeFor(7), MotionMode::kConstant);
  EXPECT_EQ(p.modeFor(8), MotionMode::kPerStep);
}

TEST(ParseMotionMode, KnownAndUnknown) {
  EXPECT_EQ(ParseMotionMode("per-step"), MotionMode::kPerStep);
  EXPECT_EQ(ParseMotionMode("constant"), MotionMode::kConstant);
  EXPECT_EQ(ParseMotionMode("smoothed"), MotionMode::kSmoothed);
  EXPECT_THROW(ParseMotionMode("linear"), std::invalid_argument);
  for (MotionMode m : {MotionMode::kPerStep, MotionMode::kConstant, MotionMode::kSmoothed})
    EXPECT_EQ(ParseMotionMode(ToString(m)), m);
}

TEST(ParseSchedule, BatchAndWindow) {
  EXPECT_EQ(ParseSchedule("batch").kind, ScheduleKind::kBatch);
  const Schedule w = ParseSchedule("window:15");
  EXPECT_EQ(w.kind, ScheduleKind::kSlidingWindow);
  EXPECT_EQ(w.window_frames, 15);
  EXPECT_EQ(ToString(w), "window:15");
  for (const char* bad : {"window:1", "window:", "window:abc", "window:5x", "sliding", ""})
    EXPECT_THROW(ParseSchedule(bad), std::invalid_argument) << bad;
}

TEST(ParseMarginalisation, KnownAndUnknown) {
  EXPECT_EQ(BackendParams().marginalisation, Marginalisation::kSparsified);
  for (Marginalisation m : {Marginalisation::kSparsified, Marginalisation::kExact})
    EXPECT_EQ(ParseMarginalisation(ToString(m)), m);
  EXPECT_EQ(ParseMarginalisation("exact"), Marginalisation::kExact);
  for (const char* bad : {"Exact", "schur", ""}) EXPECT_THROW(ParseMarginalisation(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace dslam
