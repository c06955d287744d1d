// End-to-end frames per second of ours on an image sequence (front-end, classifier, fixed-lag smoother),
// with the stages in sequence on one thread and in parallel (pipeline/staged_pipeline.h), from frames
// already in memory (without PNG decoding) and from the files (what `dslam run --methods ours` does).
// Usage: bench_pipeline [DATASET_DIR] [frames=60] [repeats=3]
// Without DATASET_DIR it renders the built-in city (the demo's scene) into a scratch folder.
// Prints the median over the repeats of each mode.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <vector>

#include "app/render_scene_command.h"
#include "app/run_command.h"
#include "bench/percentile.h"
#include "data/image_dataset.h"
#include "pipeline/image_run.h"
#include "pipeline/staged_pipeline.h"
#include "plugin/vehicle_pipeline.h"

namespace {
using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

int main(int argc, char** argv) {
  std::string dir = argc > 1 ? argv[1] : "";
  const int max_frames = argc > 2 ? std::atoi(argv[2]) : 60;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 3;
  if (max_frames < 3 || repeats < 1) {
    std::cerr << "usage: bench_pipeline [DATASET_DIR] [frames >= 3] [repeats >= 1]\n";
    return 2;
  }
  if (dir.empty()) {
    dir = (std::filesystem::temp_directory_path() / "dslam_bench_pipeline_city").string();
    dslam::RenderSceneOptions render;
    render.scenario = "city", render.frames = max_frames, render.out_dir = dir, render.quiet = true;
    if (const int status = dslam::RunRenderSceneCommand(render, std::cout, std::cerr); status != 0) return status;
  }
  dslam::RunConfig config;  // as `dslam run` by default: ours smoothed, window of 10
  config.backend.default_mode = dslam::ParseMotionMode(dslam::kRunDefaultMode);
  config.backend.schedule = dslam::ParseSchedule(dslam::RunCommandOptions().schedule.value());
  const dslam::ImageDataset data(dir, config.dataset);
  const int frames = std::min(max_frames, data.size());
  std::vector<dslam::ImageFrame> images;
  for (int k = 0; k < frames; ++k) images.push_back(data.read(k));

  std::vector<double> sequential, staged, from_files;
  for (int r = 0; r < repeats; ++r) {
    {
      dslam::VehiclePipeline pipeline(config, data.camera(), data.frameRateHz());
      const auto t0 = Clock::now();
      for (const auto& f : images) pipeline.process(f);
      pipeline.finish();
      sequential.push_back(frames / SecondsSince(t0));
    }
    {
      dslam::StagedPipeline pipeline(config, data.camera(), data.frameRateHz(), 4, {});
      const auto t0 = Clock::now();
      for (const auto& f : images) pipeline.push(f);
      pipeline.finish();
      staged.push_back(frames / SecondsSince(t0));
    }
    {
      dslam::MethodResult ours;
      const auto t0 = Clock::now();
      dslam::RunImageFrontend(data, config, frames, nullptr, nullptr, nullptr, &ours);
      from_files.push_back(frames / SecondsSince(t0));
    }
  }
  std::printf("ours on %d frames of %s (%dx%d), median of %d runs:\n", frames, dir.c_str(), data.camera().width,
              data.camera().height, repeats);
  std::printf("  in memory, stages in sequence:  %6.1f frames/s\n", dslam::bench::Percentile(sequential, 0.5));
  std::printf("  in memory, stages in parallel:  %6.1f frames/s\n", dslam::bench::Percentile(staged, 0.5));
  std::printf("  from PNG files, in parallel:    %6.1f frames/s (reading and decoding included)\n",
              dslam::bench::Percentile(from_files, 0.5));
  return 0;
}
