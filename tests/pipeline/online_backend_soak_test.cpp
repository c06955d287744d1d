// Soak test of the back-end as `dslam serve` runs it (streaming to files, collecting nothing): over a
// scene that repeats exactly, what it holds after one more cycle is what it held a cycle before. Short
// enough for CI; the RSS of a long run is printed by bench_pipeline (a benchmark, not a test).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "output/streaming_sink.h"
#include "output/trajectory_io.h"
#include "pipeline/online_backend.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

struct Footprint {
  size_t points, motions, frames, transitions, identities, solve_history;
};

Footprint Measure(const OnlineBackend& backend) {
  const Estimator& e = backend.estimator();
  const FactorGraph& g = e.graph();
  return {g.points.size(),  g.motions.size(),
          g.frames.size(),  g.transitions.size(),
          e.builder().rememberedIdentities(),
          e.solveTimesMs().size() + e.solveIterations().size() + e.solveResidualBlocks().size()};
}

TEST(OnlineBackendSoak, AsAServiceWhatItHoldsDoesNotGrowFromCycleToCycle) {
  ScenarioOptions opt;
  const int probe = 100;
  opt.num_frames = probe + 2 * kCityCycleFrames + 1;
  Sequence seq = MakeScenario("city", opt);
  RunConfig config;
  config.backend.default_mode = MotionMode::kSmoothed;
  config.backend.schedule = {ScheduleKind::kSlidingWindow, 10};
  const std::string out = (std::filesystem::temp_directory_path() / "dslam_soak_test").string();
  std::filesystem::remove_all(out);
  StreamingFileSink stream(out);
  OnlineBackend backend(config, seq.frame_rate_hz, &stream, /*collect=*/false);
  std::vector<Footprint> at;
  for (auto& frame : seq.frames) {
    backend.add(&frame);
    const int k = backend.framesAdded() - 1;
    if (k == probe || k == probe + kCityCycleFrames || k == probe + 2 * kCityCycleFrames) at.push_back(Measure(backend));
  }
  ASSERT_EQ(at.size(), 3u);
  EXPECT_GT(at[0].points, 100u);
  EXPECT_GT(at[0].motions, 0u);
  for (int c = 1; c <= 2; ++c) {
    // The same scene in the window: the same graph, give or take the tracks that started a frame apart.
    EXPECT_NEAR(static_cast<double>(at[c].points), static_cast<double>(at[0].points), 0.02 * at[0].points) << c;
    EXPECT_EQ(at[c].motions, at[0].motions) << c;
    EXPECT_EQ(at[c].frames, at[0].frames) << c;
    EXPECT_EQ(at[c].transitions, at[0].transitions) << c;
    EXPECT_LT(at[c].identities, at[0].identities * 3 / 2) << c;
    EXPECT_LE(at[c].solve_history, 3u) << c;  // the last solve's statistics only
  }
  const MethodResult result = backend.finish();
  EXPECT_TRUE(result.estimate.T_world_camera.empty());
  EXPECT_TRUE(result.online.empty());
  // Every frame's pose is in the stream.
  EXPECT_EQ(ReadTumTrajectory(out + "/camera_ours.tum").size(), seq.frames.size());
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace dslam
