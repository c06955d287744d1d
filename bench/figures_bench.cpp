// Time to draw every figure and the report of a 300-frame run (target: under 10 s).
// Usage: bench_figures [frames=300] [scratch dir]
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "app/figures_command.h"
#include "app/sim_command.h"
#include "data/frame_memory.h"

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  const int frames = argc > 1 ? std::atoi(argv[1]) : 300;
  const std::string dir = argc > 2 ? argv[2] : (std::filesystem::temp_directory_path() / "dslam_bench_figures").string();
  if (frames < 2) {
    std::cerr << "usage: bench_figures [frames >= 2] [dir]\n";
    return 2;
  }
  // The run as `dslam sim` streams it (ours and both baselines in lockstep, the files written as the
  // estimates become final), smoothed in the sliding window as `dslam run` estimates.
  dslam::SimCommandOptions sim;
  sim.scenario = "city";
  sim.frames = frames;
  sim.mode = "smoothed";
  sim.schedule = "window:10";
  sim.out_dir = dir;
  sim.quiet = true;
  sim.no_figures = true;
  std::cerr << "running the " << frames << "-frame city sequence first...\n";
  if (const int code = dslam::RunSimCommand(sim, std::cerr, std::cerr); code != 0) return code;
  for (int run = 0; run < 3; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const int code = dslam::RunFiguresCommand(dir, dslam::FigureOptions{}, std::cerr, std::cerr);
    if (code != 0) return code;
    std::cout << "all figures + report for " << frames << " frames: "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
  }
  return 0;
}
