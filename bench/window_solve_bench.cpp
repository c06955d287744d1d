// Per-frame cost of the fixed-lag smoother (window schedule) on a long `city` run, one core: mean per
// 100 frames, median and p99 after the first 100 frames. The city repeats exactly every
// 300 frames, so frame 1000 sees the same scene as frame 100: the solve time around frame 100
// (frames 90-109) and around frame 1000 (frames 990-1009) must be about equal.
// Usage: bench_window_solve [frames=1100] [window=10] [CONFIG.yaml]  (settings over the defaults, e.g. to
// compare a back-end option before and after in one binary)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numeric>

#include "backend/estimator.h"
#include "bench/percentile.h"
#include "data/frame_memory.h"
#include "frontend/dynamic_object_classifier.h"
#include "pipeline/config_yaml.h"
#include "pipeline/run_config.h"
#include "simulation/scenarios.h"

namespace {
double Mean(const std::vector<double>& v, int from, int to) {
  from = std::max(0, from);
  to = std::min<int>(v.size(), to);
  return to > from ? std::accumulate(v.begin() + from, v.begin() + to, 0.0) / (to - from) : 0.0;
}
}  // namespace

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  const int frames = argc > 1 ? std::atoi(argv[1]) : 1100;
  const int window = argc > 2 ? std::atoi(argv[2]) : 10;
  if (frames < 200 || window < 2) {
    std::cerr << "usage: bench_window_solve [frames >= 200] [window >= 2] [CONFIG.yaml]\n";
    return 2;
  }
  dslam::ScenarioOptions scenario;
  scenario.num_frames = frames;
  const dslam::Sequence seq = dslam::MakeScenario("city", scenario);
  dslam::RunConfig config;
  if (argc > 3) config = dslam::LoadRunConfig(argv[3]);
  config.backend.default_mode = dslam::MotionMode::kSmoothed;
  config.backend.schedule = {dslam::ScheduleKind::kSlidingWindow, window};
  std::vector<dslam::FrameMeasurement> labelled = seq.frames;
  dslam::LabelDynamicObjects(config.classifier, seq.frame_rate_hz, &labelled);
  dslam::Estimator estimator(config.backend, seq.frame_rate_hz);
  for (const auto& f : labelled) {
    estimator.addFrame(f);
    if ((f.frame_index + 1) % 100 == 0)
      std::cerr << "frame " << f.frame_index + 1 << "/" << frames << ": " << estimator.solveTimesMs().back()
                << " ms\n";
  }
  const auto& ms = estimator.solveTimesMs();
  const auto& blocks = estimator.solveResidualBlocks();
  std::vector<double> sizes(blocks.begin(), blocks.end());
  std::vector<double> iterations(estimator.solveIterations().begin(), estimator.solveIterations().end());
  std::cout << "city, " << frames << " frames, window " << window << " (smoothed motion, one thread)\n";
  std::cout << "frames        mean solve ms/frame   residual blocks/window   LM iterations   ms per 1000 blocks"
               " and iteration\n";
  for (int from = 0; from + 100 <= frames; from += 100) {
    const double t = Mean(ms, from, from + 100), b = Mean(sizes, from, from + 100), it = Mean(iterations, from, from + 100);
    std::printf("%4d-%-4d   %12.1f   %22.0f   %13.1f   %18.2f\n", from, from + 99, t, b, it, 1000.0 * t / (b * it));
  }
  std::printf("solve ms/frame over frames 100-%d: median %.2f, p99 %.2f\n", frames - 1,
              dslam::bench::Percentile(std::vector<double>(ms.begin() + 100, ms.end()), 0.5),
              dslam::bench::Percentile(std::vector<double>(ms.begin() + 100, ms.end()), 0.99));
  std::cout << "around frame 100 (90-109): " << Mean(ms, 90, 110) << " ms/frame, " << Mean(sizes, 90, 110)
            << " residual blocks, " << Mean(iterations, 90, 110) << " iterations\n";
  if (frames >= 1010)
    std::cout << "around frame 1000 (990-1009): " << Mean(ms, 990, 1010) << " ms/frame, " << Mean(sizes, 990, 1010)
              << " residual blocks, " << Mean(iterations, 990, 1010) << " iterations\n";
  return 0;
}
