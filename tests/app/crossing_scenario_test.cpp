// Issue 13's junction: the simulated `crossing` scenario through ours with the sliding window, as
// `dslam sim --scenario crossing --schedule window:10` runs it.
#include <gtest/gtest.h>

#include "evaluation/evaluate_run.h"
#include "output/object_summary.h"
#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"
#include "support/crossing_checks.h"

namespace dslam {
namespace {

TEST(CrossingScenario, CrossingAndOncomingCarsAreEstimatedAndTheStopAndGoCarStandsOnlyWhileStopped) {
  const Sequence seq = MakeScenario("crossing", ScenarioOptions{});
  RunConfig config;
  config.backend.default_mode = ParseMotionMode(ScenarioDefaultMotionMode("crossing"));
  config.backend.schedule = {ScheduleKind::kSlidingWindow, 10};
  RunSequenceOptions run;
  run.methods = {Method::kOurs, Method::kStaticOnly};
  const MethodOutcomes outcomes = RunSequence(seq, config, run);
  const Estimate& ours = outcomes.at(Method::kOurs).result.estimate;

  int checked = 0;
  for (const ObjectSummary& o : SummariseObjects(seq, ours)) {
    const bool crossing = o.object_id >= kCrossingFirstCrossingId && o.object_id < kCrossingFirstCrossingId + 4;
    const bool oncoming = o.object_id >= kCrossingFirstOncomingId && o.object_id < kCrossingFirstOncomingId + 2;
    if (!crossing && !oncoming) continue;
    ++checked;
    ASSERT_TRUE(o.metrics.omse_pct) << o.object_id;
    EXPECT_LT(*o.metrics.omse_pct, 5.0) << o.object_id;
    EXPECT_GE(static_cast<double>(o.frames_estimated) / o.gt_pairs, 0.9) << o.object_id;
  }
  EXPECT_EQ(checked, 6);

  // Stopped (for the classifier's half-second window): reported standing; moving again, over 1 m/s for
  // as long: reported moving. Parked: never moving.
  const test::StopAndGoCounts c = test::CheckJunctionObjects(seq, ours);
  EXPECT_GE(c.stopped, 40);
  EXPECT_EQ(c.stopped_standing, c.stopped);
  EXPECT_GE(c.going, 30);
  EXPECT_EQ(c.going_moving, c.going);
  // The camera pays nothing for the objects.
  EXPECT_LE(outcomes.at(Method::kOurs).metrics.camera.ate_m, 1.02 * outcomes.at(Method::kStaticOnly).metrics.camera.ate_m);
}

}  // namespace
}  // namespace dslam
