#include "pipeline/streamed_run.h"

#include <gtest/gtest.h>

#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"
#include "support/same_run.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

// The streamed run (frames made one at a time, methods in lockstep, evaluation by sums, files written
// as estimates become final) computes what the collected run computes, method by method, and its files
// hold the same rows.
void ExpectStreamedEqualsCollected(const std::string& scenario, int frames, const std::string& schedule) {
  SCOPED_TRACE(scenario + " " + schedule);
  ScenarioOptions opt;
  opt.num_frames = frames;
  RunConfig config;
  config.backend.default_mode = ParseMotionMode(ScenarioDefaultMotionMode(scenario));
  config.backend.schedule = ParseSchedule(schedule);

  const Sequence seq = MakeScenario(scenario, opt);
  const MethodOutcomes collected = RunSequence(seq, config);
  const std::string collected_dir = test::TempPath("collected_" + scenario + schedule);
  WriteRunOutputs(collected_dir, seq, collected, {});

  SensorSimulator simulator = MakeScenarioSimulator(scenario, opt);
  StreamedRunOptions run;
  run.out_dir = test::TempPath("streamed_" + scenario + schedule);
  int frames_seen = 0;
  run.after_frame = [&](int done) { frames_seen = done; };
  const StreamedRunResult streamed = RunStreamed(&simulator, config, run);
  EXPECT_EQ(frames_seen, frames);

  for (const auto& [method, outcome] : collected)
    test::ExpectSameMetrics(streamed.outcomes.at(method).metrics, outcome.metrics, ToString(method));

  for (const char* name : {"camera_ours.tum", "camera_static_only.tum", "camera_slam_mot.tum", "camera_gt.tum"})
    test::ExpectSameTrajectory(run.out_dir + "/" + name, collected_dir + "/" + name);
  for (const char* name : {"object_speeds.csv", "object_motions.csv", "object_speeds_slam_mot.csv", "map_points.csv",
                           "objects.csv", "object_centroids_gt.csv"})
    test::ExpectSameRows(run.out_dir + "/" + name, collected_dir + "/" + name);
}

TEST(StreamedRun, EqualsTheCollectedRunOnTheCityWithTheSlidingWindow) {
  ExpectStreamedEqualsCollected("city", 60, "window:10");
}

TEST(StreamedRun, EqualsTheCollectedRunOnThePaperScenarioInBatch) {
  ExpectStreamedEqualsCollected("paper", 25, "batch");
}

}  // namespace
}  // namespace dslam
