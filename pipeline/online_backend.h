#pragma once
// Ours as an online back-end stage: each frame's measurement is labelled by the scene-flow classifier
// (against the previous frame's) and added to the estimator, and the newest frame's estimate comes back
// at once. It computes what `dslam run` computes for ours (RunSequence labels every frame, then adds them
// in the same order), one frame at a time, keeping only the previous frame's measurement.

#include <optional>

#include "backend/estimator.h"
#include "backend/methods.h"
#include "frontend/dynamic_object_classifier.h"
#include "output/streaming_sink.h"
#include "pipeline/run_config.h"

namespace dslam {

class OnlineBackend {
 public:
  // `stream`, when given, receives the final estimates as they leave the window and each frame's online
  // pose (the result files of a run that is still going). With `collect`, the estimates are also kept
  // for finish() (runs evaluated at the end); without it (a service running for hours) nothing grows
  // with the number of frames and finish() returns only the solve statistics.
  OnlineBackend(const RunConfig& config, double frame_rate_hz, StreamingFileSink* stream = nullptr,
                bool collect = true);
  OnlineBackend(const OnlineBackend&) = delete;
  OnlineBackend& operator=(const OnlineBackend&) = delete;

  // Labels `frame` in place (its objects' static/dynamic decision) and adds it; returns the newest
  // frame's estimate, stamped with the frame's stamp. A frame it refuses (out of sequence, not a valid
  // measurement) throws std::invalid_argument before anything changed.
  FrameEstimate add(FrameMeasurement* frame);

  int framesAdded() const { return frames_added_; }
  // What it holds (the window's graph, the builder's identities, the solve statistics), for tests.
  const Estimator& estimator() const { return estimator_; }
  // Call once, after the last frame: the final estimate, each frame's online estimate, the per-frame
  // solve times (only the last one without `collect`) and the time spent in add() and finish().
  MethodResult finish();

 private:
  static EstimatorOptions SinkOptions(EstimateSink* sink, bool collect);
  EstimateSink* sinkFor(StreamingFileSink* stream, bool collect);
  struct DiscardingSink : EstimateSink {
    void cameraFinal(int, const SE3&) override {}
    void motionFinal(const ObjectMotionEstimate&) override {}
    void pointFinal(const PointEstimate&) override {}
  };
  DiscardingSink discard_;

  StreamingFileSink* stream_;
  bool collect_;
  CollectingSink collected_;
  TeeSink tee_;
  DynamicObjectClassifier classifier_;
  Estimator estimator_;
  std::optional<FrameMeasurement> previous_;
  MethodResult result_;
  int frames_added_ = 0;
};

}  // namespace dslam
