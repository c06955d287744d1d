// Memory of a long simulated run, as `dslam sim --scenario SCENARIO --schedule window:10` runs it
// (frames made one at a time, the three methods side by side, results streamed to files): prints the
// process' resident memory before the first frame (the simulated world is built by then) and every
// 1000 frames, and the ratio of the last figure to the one at frame 2000. A run must not grow with its
// length.
// Usage: bench_long_sim [frames=20000] [scenario=city]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "app/sim_command.h"
#include "bench/rss.h"
#include "data/frame_memory.h"
#include "pipeline/streamed_run.h"
#include "simulation/scenarios.h"

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  const int frames = argc > 1 ? std::atoi(argv[1]) : 20000;
  const std::string scenario = argc > 2 ? argv[2] : "city";
  if (frames < 2) {
    std::cerr << "usage: bench_long_sim [frames >= 2] [scenario]\n";
    return 2;
  }
  dslam::SimCommandOptions options;  // the command's defaults
  options.scenario = scenario;
  options.schedule = "window:10";
  const dslam::RunConfig config = dslam::BuildRunConfig(options, dslam::EntryPoint::kSim, scenario);
  dslam::ScenarioOptions world;
  world.num_frames = frames;
  std::printf("building the %s world for %d frames ...\n", scenario.c_str(), frames);
  dslam::SensorSimulator simulator = dslam::MakeScenarioSimulator(scenario, world);
  const double rss_world = dslam::bench::RssMb();
  std::printf("  before the first frame: RSS %7.1f MB\n", rss_world);

  dslam::StreamedRunOptions run;
  run.out_dir = (std::filesystem::temp_directory_path() / "dslam_bench_long_sim").string();
  double rss_at_2000 = 0.0, rss_last = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  run.after_frame = [&](int done) {
    if (done % 1000 != 0 && done != frames) return;
    rss_last = dslam::bench::RssMb();
    if (done == 2000) rss_at_2000 = rss_last;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("  frame %6d: RSS %7.1f MB, %.1f frames/s\n", done, rss_last, done / s);
    std::fflush(stdout);
  };
  const dslam::StreamedRunResult result = dslam::RunStreamed(&simulator, config, run);
  std::printf("after the evaluation and the last files: RSS %7.1f MB\n", dslam::bench::RssMb());
  if (rss_at_2000 > 0.0) std::printf("RSS at frame %d / at frame 2000: %.3f\n", frames, rss_last / rss_at_2000);
  const auto& ours = result.outcomes.at(dslam::Method::kOurs).metrics;
  std::printf("ours: RTE %.3f %%, OMSE %.3f %% (results in %s)\n", ours.camera.rte_pct.value_or(0.0),
              ours.objects && ours.objects->omse_pct ? *ours.objects->omse_pct : 0.0, run.out_dir.c_str());
  return 0;
}
