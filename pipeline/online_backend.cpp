#include "pipeline/online_backend.h"

#include <chrono>
#include <stdexcept>

#include "data/frame_timing.h"

namespace dslam {

// Called from the constructor's initialiser list, before methods_ is built (members above it exist).
std::map<Method, EstimateSink*> OnlineBackend::methodSinks(const std::map<Method, EstimateSink*>& sinks) {
  if (collect_) ours_sinks_.add(&collected_);
  ours_sinks_.add(stream_);
  std::map<Method, EstimateSink*> all = sinks;
  if (const auto it = sinks.find(Method::kOurs); it != sinks.end()) ours_sinks_.add(it->second);
  // Ours runs where its estimates go somewhere, and always alone (a service's stage is ours).
  if (!ours_sinks_.empty() || all.empty()) all[Method::kOurs] = &ours_sinks_;
  return all;
}

OnlineBackend::OnlineBackend(const RunConfig& config, double frame_rate_hz, StreamingFileSink* stream, bool collect,
                             const std::map<Method, EstimateSink*>& sinks)
    : stream_(stream), collect_(collect), methods_(config, frame_rate_hz, methodSinks(sinks), collect) {}

FrameEstimate OnlineBackend::add(FrameMeasurement* frame) {
  const auto start = std::chrono::steady_clock::now();
  // The estimator's own checks, before the classifier and the files see the frame.
  if (const std::string bad = FindInvalidMeasurement(*frame, frames_added_); !bad.empty())
    throw std::invalid_argument(bad);
  if (stream_) stream_->frameStamp(frames_added_, frame->t_ns);
  const FrameEstimate latest = *methods_.add(frame);
  ++frames_added_;
  if (collect_) result_.online.push_back(latest);
  if (stream_) stream_->onlinePose(latest.t_ns, latest.T_world_camera);
  result_.wall_time_s += SecondsSince(start);
  return latest;
}

MethodResult OnlineBackend::finish() {
  const auto start = std::chrono::steady_clock::now();
  methods_.finish();
  if (collect_) result_.estimate = std::move(collected_.estimate);
  if (stream_) stream_->finish();
  if (methods_.ours()) result_.solve_times_ms = methods_.ours()->solveTimesMs();
  result_.wall_time_s += SecondsSince(start);
  return std::move(result_);
}

}  // namespace dslam
