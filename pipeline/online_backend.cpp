#include "pipeline/online_backend.h"

#include <chrono>

namespace dslam {
namespace {
double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

OnlineBackend::OnlineBackend(const RunConfig& config, double frame_rate_hz)
    : classifier_(config.classifier, frame_rate_hz), estimator_(config.backend, frame_rate_hz) {}

FrameEstimate OnlineBackend::add(FrameMeasurement* frame) {
  const auto start = std::chrono::steady_clock::now();
  if (previous_) classifier_.label(*previous_, frame);
  estimator_.addFrame(*frame);
  previous_ = *frame;
  ++frames_added_;
  FrameEstimate latest = estimator_.latest();
  latest.t_ns = frame->t_ns;
  result_.online.push_back(latest);
  result_.wall_time_s += SecondsSince(start);
  return latest;
}

MethodResult OnlineBackend::finish() {
  const auto start = std::chrono::steady_clock::now();
  result_.estimate = estimator_.finish();
  result_.solve_times_ms = estimator_.solveTimesMs();
  result_.wall_time_s += SecondsSince(start);
  return std::move(result_);
}

}  // namespace dslam
