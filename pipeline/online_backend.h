#pragma once
// Ours (and, when asked, the baselines beside it) as an online back-end stage: each frame's measurement
// is labelled by the scene-flow classifier (against the previous frame's) and added to every method
// (pipeline/lockstep_methods.h), and ours' newest estimate comes back at once. Ours computes what
// RunMethod computes on the same labelled frames, one frame at a time, keeping only the previous
// frame's measurement.

#include <map>

#include "backend/estimator.h"
#include "backend/methods.h"
#include "output/streaming_sink.h"
#include "pipeline/lockstep_methods.h"
#include "pipeline/run_config.h"

namespace dslam {

class OnlineBackend {
 public:
  // `stream`, when given, receives the final estimates as they leave the window and each frame's online
  // pose (the result files of a run that is still going). With `collect`, the estimates are also kept
  // for finish() (runs evaluated at the end); without it (a service running for hours) nothing grows
  // with the number of frames and finish() returns only the solve statistics. `sinks` receive final
  // estimates too: ours' (beside the stream and the collection) and the baselines' (static-only,
  // SLAM+MOT), which then run in lockstep with ours; each must outlive the back-end.
  OnlineBackend(const RunConfig& config, double frame_rate_hz, StreamingFileSink* stream = nullptr,
                bool collect = true, const std::map<Method, EstimateSink*>& sinks = {});
  OnlineBackend(const OnlineBackend&) = delete;
  OnlineBackend& operator=(const OnlineBackend&) = delete;

  // Labels `frame` in place (its objects' static/dynamic decision) and adds it; returns the newest
  // frame's estimate, stamped with the frame's stamp (ours', or static-only's when ours has nowhere to go:
  // no collection, stream or sink of its own). A frame it refuses (out of sequence, not a valid
  // measurement) throws std::invalid_argument before anything changed.
  FrameEstimate add(FrameMeasurement* frame);

  int framesAdded() const { return frames_added_; }
  // What ours holds (the window's graph, the builder's identities, the solve statistics), for tests; ours
  // must run.
  const Estimator& estimator() const { return *methods_.ours(); }
  // Seconds a method spent in its estimators so far (pipeline/lockstep_methods.h).
  double wallTimeS(Method method) const { return methods_.wallTimeS(method); }
  // Call once, after the last frame: the final estimate, each frame's online estimate, the per-frame
  // solve times (only the last one without `collect`) and the time spent in add() and finish().
  MethodResult finish();

 private:
  std::map<Method, EstimateSink*> methodSinks(const std::map<Method, EstimateSink*>& sinks);

  StreamingFileSink* stream_;
  bool collect_;
  CollectingSink collected_;
  TeeSink ours_sinks_;  // the collection, the stream and the caller's sink for ours, each when there is one
  LockstepMethods methods_;
  MethodResult result_;
  int frames_added_ = 0;
};

}  // namespace dslam
