// End-to-end frames per second of ours on an image sequence (front-end, classifier, fixed-lag smoother),
// with the stages in sequence on one thread and in parallel (pipeline/staged_pipeline.h), from frames
// already in memory (without PNG decoding) and from the files (what `dslam run --methods ours` does).
// Usage: bench_pipeline [DATASET_DIR] [frames=60] [repeats=3] [long_run_frames=0]
// Without DATASET_DIR it renders the built-in city (the demo's scene) into a scratch folder.
// Prints the median over the repeats of each mode. With long_run_frames > 0 it then runs `dslam run`'s
// stream (the three methods in lockstep, results streamed to files) over that many frames, the sequence
// played forwards and backwards in turn (a continuous drive), and prints the process' resident memory
// every 1000 frames: a run must not grow with its length.
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

// `dslam run` over `frames` frames of the dataset played forwards and backwards in turn (a continuous
// drive): the three methods in lockstep, their files streamed, nothing collected; the process' resident
// memory every 1000 frames. A run must not grow with its length.
void LongRun(const dslam::RunConfig& config, const dslam::ImageDataset& data, int frames) {
  dslam::ImageRunOptions run;
  run.out_dir = (std::filesystem::temp_directory_path() / "dslam_bench_pipeline_long").string();
  run.max_frames = frames;
  run.ping_pong = true;
  std::printf("long run as dslam run runs (three methods, streamed to %s):\n", run.out_dir.c_str());
  double rss_at_1000 = 0.0, rss_last = 0.0;
  const auto t0 = Clock::now();
  run.after_frame = [&](int done) {
    if (done % 1000 != 0) return;
    rss_last = RssMb();
    if (done == 1000) rss_at_1000 = rss_last;
    std::printf("  frame %6d: RSS %7.1f MB, %.1f frames/s\n", done, rss_last, done / SecondsSince(t0));
    std::fflush(stdout);
  };
  dslam::RunImageStreamed(data, config, run);
  if (rss_at_1000 > 0.0) std::printf("RSS at the last thousand / at frame 1000: %.3f\n", rss_last / rss_at_1000);
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
  const dslam::RunConfig config = dslam::DefaultRunConfig(dslam::EntryPoint::kRun);  // ours smoothed, window of 10
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
  if (long_run_frames > 0) LongRun(config, data, long_run_frames);
  return 0;
}
