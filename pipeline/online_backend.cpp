#include "pipeline/online_backend.h"

#include <chrono>
#include <stdexcept>

#include "data/frame_timing.h"

namespace dslam {

EstimatorOptions OnlineBackend::SinkOptions(EstimateSink* sink, bool collect) {
  EstimatorOptions options;
  options.sink = sink;
  options.keep_solve_history = collect;
  return options;
}

// Without a stream the estimator collects by itself (null sink).
EstimateSink* OnlineBackend::sinkFor(StreamingFileSink* stream, bool collect) {
  if (!stream) return collect ? nullptr : &discard_;
  return collect ? static_cast<EstimateSink*>(&tee_) : stream;
}

OnlineBackend::OnlineBackend(const RunConfig& config, double frame_rate_hz, StreamingFileSink* stream, bool collect)
    : stream_(stream),
      collect_(collect),
      tee_(&collected_, stream),
      classifier_(config.classifier, frame_rate_hz),
      estimator_(config.backend, frame_rate_hz, SinkOptions(sinkFor(stream, collect), collect)) {}

FrameEstimate OnlineBackend::add(FrameMeasurement* frame) {
  const auto start = std::chrono::steady_clock::now();
  // The estimator's own checks, before the classifier and the files see the frame.
  if (const std::string bad = FindInvalidMeasurement(*frame, frames_added_); !bad.empty())
    throw std::invalid_argument(bad);
  if (previous_) classifier_.label(*previous_, frame);
  if (stream_) stream_->frameStamp(frames_added_, frame->t_ns);
  estimator_.addFrame(*frame);
  previous_ = *frame;
  ++frames_added_;
  FrameEstimate latest = estimator_.latest();
  latest.t_ns = frame->t_ns;
  if (collect_) result_.online.push_back(latest);
  if (stream_) stream_->onlinePose(latest.t_ns, latest.T_world_camera);
  result_.wall_time_s += SecondsSince(start);
  return latest;
}

MethodResult OnlineBackend::finish() {
  const auto start = std::chrono::steady_clock::now();
  result_.estimate = estimator_.finish();
  if (stream_) {
    result_.estimate = std::move(collected_.estimate);
    stream_->finish();
  }
  result_.solve_times_ms = estimator_.solveTimesMs();
  result_.wall_time_s += SecondsSince(start);
  return std::move(result_);
}

}  // namespace dslam
