// Per-frame cost of the sliding-window schedule on a long `city` run: prints the mean solve time
// around frame 100 and around frame 1000. Constant cost means the two are about equal.
// Usage: bench_window_solve [frames=1100] [window=10]
#include <cstdlib>
#include <iostream>
#include <numeric>

#include "backend/methods.h"
#include "frontend/dynamic_object_classifier.h"
#include "pipeline/run_config.h"
#include "simulation/scenarios.h"

namespace {
double MeanAround(const std::vector<double>& v, int centre, int half_width) {
  const int lo = std::max(0, centre - half_width), hi = std::min<int>(v.size(), centre + half_width);
  if (hi <= lo) return 0.0;
  return std::accumulate(v.begin() + lo, v.begin() + hi, 0.0) / (hi - lo);
}
}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::atoi(argv[1]) : 1100;
  const int window = argc > 2 ? std::atoi(argv[2]) : 10;
  if (frames < 120 || window < 2) {
    std::cerr << "usage: bench_window_solve [frames >= 120] [window >= 2]\n";
    return 2;
  }
  dslam::ScenarioOptions scenario;
  scenario.num_frames = frames;
  const dslam::Sequence seq = dslam::MakeScenario("city", scenario);
  dslam::RunConfig config;
  config.backend.schedule.kind = dslam::ScheduleKind::kSlidingWindow;
  config.backend.schedule.window_frames = window;
  std::vector<dslam::FrameMeasurement> labelled = seq.frames;
  dslam::LabelDynamicObjects(config.classifier, seq.frame_rate_hz, &labelled);
  const auto result = dslam::RunMethod(dslam::Method::kOurs, config.backend, seq.frame_rate_hz, labelled);
  const auto& ms = result.solve_times_ms;
  std::cout << "city, " << frames << " frames, window " << window << ", total " << result.wall_time_s << " s\n";
  std::cout << "mean solve ms/frame around frame 100: " << MeanAround(ms, 100, 20) << "\n";
  if (frames > 1020) std::cout << "mean solve ms/frame around frame 1000: " << MeanAround(ms, 1000, 20) << "\n";
  std::cout << "mean solve ms/frame around the last frame: " << MeanAround(ms, frames - 21, 20) << "\n";
  return 0;
}
