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

  EXPECT_EQ(test::CheckJunctionTraffic(seq, ours, 0.9), 6);

  // Stopped (for the classifier's half-second window): reported standing; moving again, over 1 m/s for
  // as long: reported moving. Parked: never moving.
  test::CheckJunctionStopAndGoAndParked(seq, ours, 30);
  // The camera pays nothing for the objects.
  EXPECT_LE(outcomes.at(Method::kOurs).metrics.camera.ate_m, 1.02 * outcomes.at(Method::kStaticOnly).metrics.camera.ate_m);
}

}  // namespace
}  // namespace dslam
