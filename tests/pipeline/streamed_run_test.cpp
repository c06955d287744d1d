#include "pipeline/streamed_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "output/result_reader.h"
#include "output/trajectory_io.h"
#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

void ExpectNear(const std::optional<double>& streamed, const std::optional<double>& collected, const std::string& what) {
  ASSERT_EQ(streamed.has_value(), collected.has_value()) << what;
  if (streamed) {
    EXPECT_NEAR(*streamed, *collected, 1e-9 * std::max(1.0, std::abs(*collected))) << what;
  }
}

void ExpectSameMetrics(const MethodMetrics& streamed, const MethodMetrics& collected, const std::string& what) {
  ExpectNear(streamed.camera.rte_pct, collected.camera.rte_pct, what + " RTE");
  ExpectNear(streamed.camera.rre_deg_per_m, collected.camera.rre_deg_per_m, what + " RRE");
  ExpectNear(streamed.camera.ate_m, collected.camera.ate_m, what + " ATE");
  ExpectNear(streamed.rse_pct, collected.rse_pct, what + " RSE");
  ASSERT_EQ(streamed.objects.has_value(), collected.objects.has_value()) << what;
  if (!collected.objects) return;
  const ObjectMetrics &s = *streamed.objects, &c = *collected.objects;
  EXPECT_EQ(s.gt_pairs, c.gt_pairs) << what;
  EXPECT_EQ(s.estimated_pairs, c.estimated_pairs) << what;
  EXPECT_GT(c.estimated_pairs, 0) << what;
  ExpectNear(s.omte_pct, c.omte_pct, what + " OMTE");
  ExpectNear(s.omse_pct, c.omse_pct, what + " OMSE");
  ExpectNear(s.static_mean_speed_mps, c.static_mean_speed_mps, what + " static speed");
}

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
    ExpectSameMetrics(streamed.outcomes.at(method).metrics, outcome.metrics, ToString(method));

  // Trajectories line for line; object tables and map points as sets of rows.
  for (const char* name : {"camera_ours.tum", "camera_static_only.tum", "camera_slam_mot.tum", "camera_gt.tum"}) {
    std::vector<int64_t> t_streamed, t_collected;
    const auto a = ReadTumTrajectory(run.out_dir + "/" + name, &t_streamed);
    const auto b = ReadTumTrajectory(collected_dir + "/" + name, &t_collected);
    ASSERT_EQ(a.size(), b.size()) << name;
    EXPECT_EQ(t_streamed, t_collected) << name;
    for (size_t k = 0; k < a.size(); ++k)
      ASSERT_LT((a[k].translation() - b[k].translation()).norm(), 1e-6) << name << " " << k;
  }
  for (const char* name : {"object_speeds.csv", "object_motions.csv", "object_speeds_slam_mot.csv", "map_points.csv",
                           "objects.csv", "object_centroids_gt.csv"}) {
    const CsvTable a = ReadCsv(run.out_dir + "/" + name), b = ReadCsv(collected_dir + "/" + name);
    EXPECT_EQ(a.header, b.header) << name;
    EXPECT_EQ(std::multiset<std::vector<std::string>>(a.rows.begin(), a.rows.end()),
              std::multiset<std::vector<std::string>>(b.rows.begin(), b.rows.end()))
        << name;
    EXPECT_FALSE(a.rows.empty()) << name;
  }
}

TEST(StreamedRun, EqualsTheCollectedRunOnTheCityWithTheSlidingWindow) {
  ExpectStreamedEqualsCollected("city", 60, "window:10");
}

TEST(StreamedRun, EqualsTheCollectedRunOnThePaperScenarioInBatch) {
  ExpectStreamedEqualsCollected("paper", 25, "batch");
}

}  // namespace
}  // namespace dslam
