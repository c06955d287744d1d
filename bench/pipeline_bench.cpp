// End-to-end frames per second of ours on an image sequence (front-end, classifier, fixed-lag smoother),
// with the stages in sequence on one thread and in parallel (pipeline/staged_pipeline.h), from frames
// already in memory (without PNG decoding) and from the files (what `dslam run --methods ours` does).
// Usage: bench_pipeline [DATASET_DIR] [frames=60] [repeats=3] [long_run_frames=0]
// Without DATASET_DIR it renders the built-in city (the demo's scene) into a scratch folder.
// Prints the median over the repeats of each mode. With long_run_frames > 0 it then runs the staged
// pipeline as `serve` does (results streamed to files, nothing collected) over that many frames, the
// sequence played forwards and backwards in turn (a continuous drive), and prints the process' resident
// memory every 1000 frames: a service must not grow.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

#include "app/run_command.h"
#include "bench/percentile.h"
#include "bench/rendered_city.h"
#include "bench/rss.h"
#include "data/frame_memory.h"
#include "data/image_dataset.h"
#include "pipeline/image_run.h"
#include "pipeline/staged_pipeline.h"
#include "pipeline/vehicle_pipeline.h"

namespace {
using Clock = std::chrono::steady_clock;
using dslam::SecondsSince;

using dslam::bench::RssMb;

// The frame at step i of a forwards-and-backwards replay, stamped and numbered as the i-th frame.
dslam::ImageFrame PingPong(const std::vector<dslam::ImageFrame>& images, int i, int64_t period_ns) {
  const int n = static_cast<int>(images.size()), cycle = 2 * (n - 1);
  const int phase = i % cycle;
  const bool forwards = phase < n;  // k = 0 .. n-1, then n-2 .. 1 backwards
  const int k = forwards ? phase : cycle - phase;
  dslam::ImageFrame f = images[k];
  f.t_ns = static_cast<int64_t>(i) * period_ns;
  f.frame_index = i;
  // Backwards, the increment into k is the inverse of the recorded one into k+1.
  if (i == 0) f.odometry.reset();
  else if (!forwards && images[k + 1].odometry) {
    f.odometry = images[k + 1].odometry;
    f.odometry->T_prev_curr = images[k + 1].odometry->T_prev_curr.inverse();
  } else if (forwards && k == 0 && images[1].odometry) {
    f.odometry = images[1].odometry;  // turning at the first frame: from frame 1 back to 0 and on to 1
    f.odometry->T_prev_curr = images[1].odometry->T_prev_curr.inverse();
  }
  return f;
}

void LongRun(const dslam::RunConfig& config, const dslam::ImageDataset& data,
             const std::vector<dslam::ImageFrame>& images, int frames) {
  const std::string out = (std::filesystem::temp_directory_path() / "dslam_bench_pipeline_long").string();
  dslam::StreamingFileSink stream(out);
  dslam::StagedPipeline pipeline(config, data.camera(), data.frameRateHz(), 4, {}, &stream, /*collect=*/false);
  const int64_t period_ns = static_cast<int64_t>(1e9 / data.frameRateHz());
  std::printf("long run as serve runs (streamed to %s, nothing collected):\n", out.c_str());
  double rss_at_2000 = 0.0;
  const auto t0 = Clock::now();
  for (int i = 0; i < frames; ++i) {
    pipeline.push(PingPong(images, i, period_ns));
    if ((i + 1) % 1000 == 0) {
      const double rss = RssMb();
      if (i + 1 == 2000) rss_at_2000 = rss;
      std::printf("  frame %6d: RSS %7.1f MB, %.1f frames/s\n", i + 1, rss, (i + 1) / SecondsSince(t0));
    }
  }
  pipeline.finish();
  if (rss_at_2000 > 0.0) std::printf("RSS at the end / at frame 2000: %.3f\n", RssMb() / rss_at_2000);
}
}  // namespace

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  std::string dir = argc > 1 ? argv[1] : "";
  const int max_frames = argc > 2 ? std::atoi(argv[2]) : 60;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 3;
  const int long_run_frames = argc > 4 ? std::atoi(argv[4]) : 0;
  if (max_frames < 3 || repeats < 1 || long_run_frames < 0) {
    std::cerr << "usage: bench_pipeline [DATASET_DIR] [frames >= 3] [repeats >= 1] [long_run_frames >= 0]\n";
    return 2;
  }
  dir = dslam::bench::DatasetOrRenderedCity(dir, max_frames, "dslam_bench_pipeline_city");
  if (dir.empty()) return 1;
  dslam::RunConfig config;  // as `dslam run` by default: ours smoothed, window of 10
  config.backend.default_mode = dslam::ParseMotionMode(dslam::kRunDefaultMode);
  config.backend.schedule = dslam::ParseSchedule(dslam::RunCommandOptions().default_schedule.value());
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
      dslam::ImageRunOptions run;
      run.methods = {dslam::Method::kOurs};
      run.max_frames = frames;
      const auto t0 = Clock::now();
      dslam::RunImageStreamed(data, config, run);
      from_files.push_back(frames / SecondsSince(t0));
    }
  }
  std::printf("ours on %d frames of %s (%dx%d), median of %d runs:\n", frames, dir.c_str(), data.camera().width,
              data.camera().height, repeats);
  std::printf("  in memory, stages in sequence:  %6.1f frames/s\n", dslam::bench::Percentile(sequential, 0.5));
  std::printf("  in memory, stages in parallel:  %6.1f frames/s\n", dslam::bench::Percentile(staged, 0.5));
  std::printf("  from PNG files, in parallel:    %6.1f frames/s (reading and decoding included)\n",
              dslam::bench::Percentile(from_files, 0.5));
  if (long_run_frames > 0) LongRun(config, data, images, long_run_frames);
  return 0;
}
